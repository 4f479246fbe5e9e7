"""Truth tables of the ten control nodes: children that complete, fail, err or keep working."""

from __future__ import annotations

import pytest

from polynav.errors import InvalidRequest
from polynav.tasks.control import (
    CONTROLS,
    Fallback,
    Flip,
    ForceFail,
    ForceSuccess,
    Loop,
    Parallel,
    RestartSequence,
    RetrySequence,
    RetryUntilSuccess,
    Sequence,
)
from tests.unit.tasks.scripted import S, Scripted, run_of, tick_until_final

C, F, E, W = S.COMPLETE, S.FAIL, S.ERROR, S.WORKING


def test_the_ten_control_types_of_the_document() -> None:
    assert sorted(CONTROLS) == sorted([
        "sequence", "parallel", "fallback", "flip", "loop", "force_fail", "force_success",
        "restart_sequence", "retry_sequence", "retry_until_success"])


@pytest.mark.parametrize(("ends", "state", "started"), [
    ((C, C, C), C, [1, 1, 1]),
    ((C, F, C), F, [1, 1, 0]),   # stops at the first FAIL; the rest stay WAITTING
    ((C, E, C), E, [1, 1, 0]),
    ((F, C, C), F, [1, 0, 0]),
])
def test_sequence(ends: tuple[S, ...], state: S, started: list[int]) -> None:
    leaves = [Scripted(e) for e in ends]
    node = Sequence(list(leaves))
    run = run_of()
    tick_until_final(node, run)
    assert node.state is state
    assert [leaf.starts for leaf in leaves] == started
    assert all(leaf.state is S.WAITTING for leaf, n in zip(leaves, started, strict=True) if n == 0)


def test_sequence_waits_for_a_working_child() -> None:
    node = Sequence([Scripted(W), Scripted(C)])
    run = run_of()
    for _ in range(5):
        assert node.tick(run) is W
    assert node.children[1].state is S.WAITTING


def test_a_plain_task_with_loop_flag_runs_again_and_counts() -> None:
    node = Sequence([Scripted(C), Scripted(C)], loop_flag=True)
    run = run_of()
    for _ in range(5):
        node.tick(run)
    assert node.state is W and node.loop_count == 5  # one pass per tick, never a spin


@pytest.mark.parametrize(("ends", "count", "state"), [
    ((C, C, C), 0, C),        # 0: every child
    ((C, F, C), 0, F),
    ((C, F, C), 2, C),        # reaching the count completes
    ((F, F, C), 2, F),        # can no longer be reached
    ((C, E, C), 1, E),
    ((C, W, W), 1, C),        # done once the count is reached: the others are cancelled
])
def test_parallel(ends: tuple[S, ...], count: int, state: S) -> None:
    leaves = [Scripted(e) for e in ends]
    node = Parallel(list(leaves), success_count=count)
    run = run_of()
    tick_until_final(node, run)
    assert node.state is state
    assert all(leaf.starts == 1 for leaf in leaves)  # all at once
    assert not any(leaf.state.active for leaf in leaves)


def test_parallel_keeps_working_while_the_count_may_still_be_reached() -> None:
    node = Parallel([Scripted(F), Scripted(W), Scripted(W)], success_count=2)
    run = run_of()
    for _ in range(3):
        assert node.tick(run) is W


@pytest.mark.parametrize(("first", "second", "state", "second_started"), [
    (C, C, C, 0),
    (F, C, C, 1),
    (F, F, F, 1),
    (E, C, E, 0),
    (F, E, E, 1),
])
def test_fallback(first: S, second: S, state: S, second_started: int) -> None:
    b = Scripted(second)
    node = Fallback([Scripted(first), b])
    tick_until_final(node, run_of())
    assert node.state is state and b.starts == second_started


@pytest.mark.parametrize(("cls", "child", "state"), [
    (Flip, C, F), (Flip, F, C), (Flip, E, E),
    (ForceFail, C, F), (ForceFail, F, F), (ForceFail, E, E),
    (ForceSuccess, C, C), (ForceSuccess, F, C), (ForceSuccess, E, E),
])
def test_decorators(cls: type[Flip], child: S, state: S) -> None:
    node = cls([Scripted(child)])
    tick_until_final(node, run_of())
    assert node.state is state


@pytest.mark.parametrize("cls", [Flip, ForceFail, ForceSuccess])
def test_decorators_wait_for_a_working_child(cls: type[Flip]) -> None:
    node = cls([Scripted(W)])
    run = run_of()
    assert node.tick(run) is W and node.tick(run) is W


@pytest.mark.parametrize(("ends", "target", "state", "loops"), [
    ((C, C), 3, C, 3),
    ((C, F), 3, F, 0),
    ((C, E), 3, E, 0),
])
def test_loop(ends: tuple[S, ...], target: int, state: S, loops: int) -> None:
    leaves = [Scripted(e) for e in ends]
    node = Loop(list(leaves), target_loop_count=target)
    tick_until_final(node, run_of())
    assert node.state is state and node.loop_count == loops


def test_loop_with_count_zero_runs_for_ever() -> None:
    node = Loop([Scripted(C)], target_loop_count=0)
    run = run_of()
    for _ in range(50):
        assert node.tick(run) is W
    assert node.loop_count == 50


def test_restart_sequence_starts_again_from_the_first_child() -> None:
    first = Scripted(C)
    second = Scripted(F, F, C)  # fails twice, then completes
    node = RestartSequence([first, second])
    tick_until_final(node, run_of())
    assert node.state is C and first.starts == 3 and second.starts == 3


def test_restart_sequence_error_and_working() -> None:
    node = RestartSequence([Scripted(C), Scripted(E)])
    tick_until_final(node, run_of())
    assert node.state is E
    node = RestartSequence([Scripted(W)])
    run = run_of()
    assert node.tick(run) is W and node.tick(run) is W


def test_retry_sequence_runs_the_failed_child_again() -> None:
    first = Scripted(C)
    second = Scripted(F, F, C)
    node = RetrySequence([first, second])
    tick_until_final(node, run_of())
    assert node.state is C and first.starts == 1 and second.starts == 3
    node = RetrySequence([Scripted(E)])
    tick_until_final(node, run_of())
    assert node.state is E


def test_retry_until_success() -> None:
    child = Scripted(F, F, F, C)
    node = RetryUntilSuccess([child])
    tick_until_final(node, run_of())
    assert node.state is C and child.starts == 4
    node = RetryUntilSuccess([Scripted(F, E)])
    tick_until_final(node, run_of())
    assert node.state is E
    node = RetryUntilSuccess([Scripted(W)])
    run = run_of()
    assert node.tick(run) is W


def test_an_error_deep_in_the_tree_stops_the_whole_tree() -> None:
    working = Scripted(W)
    deep = Sequence([Scripted(C), Fallback([Scripted(E), Scripted(C)])])
    root = Parallel([working, RetryUntilSuccess([deep])], success_count=0)
    tick_until_final(root, run_of())
    assert root.state is E
    assert working.state is S.CANCELLED and working.halted == 1


def test_pause_freezes_the_subtree_and_resume_goes_on() -> None:
    leaf = Scripted(C, work=3)
    root = Sequence([leaf, Scripted(C)])
    run = run_of()
    root.tick(run)
    assert root.pause(run) and leaf.state is S.PAUSED and leaf.held == 1
    for _ in range(10):
        root.tick(run)
    assert root.state is S.PAUSED and leaf.left == 2
    assert root.resume(run)
    tick_until_final(root, run)
    assert root.state is C


def test_cancel_ends_every_node_cancelled_and_stops_what_runs() -> None:
    leaf = Scripted(W)
    later = Scripted(C)
    root = Sequence([leaf, later])
    run = run_of()
    root.tick(run)
    assert root.cancel(run)
    assert [n.state for n in root.walk()] == [S.CANCELLED] * 3
    assert leaf.halted == 1 and later.halted == 0  # only what ran is stopped
    assert not root.cancel(run)


def test_a_child_cancelled_alone_counts_as_failed_so_a_fallback_branches() -> None:
    first = Scripted(W)
    root = Fallback([first, Scripted(C)])
    run = run_of()
    root.tick(run)
    first.cancel(run)
    tick_until_final(root, run)
    assert root.state is C


def test_a_paused_child_keeps_its_parent_waiting() -> None:
    first = Scripted(C, work=5)
    root = Sequence([first, Scripted(C)])
    run = run_of()
    root.tick(run)
    first.pause(run)
    for _ in range(10):
        assert root.tick(run) is W
    first.resume(run)
    tick_until_final(root, run)
    assert root.state is C


@pytest.mark.parametrize(("cls", "count"), [
    (Fallback, 1), (Fallback, 3), (Flip, 2), (ForceFail, 0), (ForceSuccess, 2),
    (RetryUntilSuccess, 2), (Sequence, 0), (Parallel, 0), (Loop, 0),
])
def test_wrong_child_counts_are_refused(cls: type[Sequence], count: int) -> None:
    with pytest.raises(InvalidRequest, match="child"):
        cls([Scripted(C) for _ in range(count)])


@pytest.mark.parametrize("count", [-1, 4, True, 1.5])
def test_a_success_count_out_of_range_is_refused(count: object) -> None:
    with pytest.raises(InvalidRequest, match="success_count"):
        Parallel([Scripted(C)] * 3, success_count=count)  # type: ignore[arg-type]
