from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.mapping import evaluation
from polynav.mapping.errors import RelationsError

TRAJECTORY = """# t x y theta
0.000000 0 0 0
1.000000 1 0 1.5707963267948966
2.000000 1 1 1.5707963267948966
"""
RELATIONS = """0.000000 1.000000 1 0 0 0 0 1.5707963267948966
0.000000 2.000000 1 1.1 0 0 0 1.5707963267948966
1.000000 2.000000 1 0 0 0 0 0.1
0.500000 2.000000 0 0 0 0 0 0
"""


def _score(**kwargs: object) -> evaluation.RelationError:
    times, poses = evaluation.parse_trajectory(TRAJECTORY.splitlines())
    relations = evaluation.parse_relations(RELATIONS.splitlines())
    return evaluation.relation_error(times, poses, relations, **kwargs)  # type: ignore[arg-type]


def test_exact_relations_score_cartographer_error_convention() -> None:
    result = _score(exact_only=True)
    trans = np.array([0.0, 0.1, 2.0 * math.sin(0.05)])
    rot = np.array([0.0, 0.0, math.degrees(0.1)])
    assert (result.relations, result.exact, result.skipped) == (3, 3, 1)
    assert result.trans_mean == pytest.approx(trans.mean(), abs=1e-12)
    assert result.trans_std == pytest.approx(trans.std(ddof=1), abs=1e-12)
    assert result.trans2_mean == pytest.approx((trans**2).mean(), abs=1e-12)
    assert result.rot_mean == pytest.approx(math.degrees(0.1) / 3.0, abs=1e-9)
    assert result.rot_std == pytest.approx(rot.std(ddof=1), abs=1e-9)
    assert result.rot2_mean == pytest.approx((rot**2).mean(), abs=1e-9)


def test_a_stamp_between_poses_is_interpolated() -> None:
    result = _score()
    assert (result.relations, result.exact, result.skipped) == (4, 3, 0)
    # At t = 0.5 the pose is (0.5, 0, 45°); to (1, 1, 90°) that is a motion whose error against
    # the identity relation is its own size.
    a = np.array([[0.5, 0.0, math.pi / 4]])
    b = np.array([[1.0, 1.0, math.pi / 2]])
    d = evaluation.relative(a, b)[0]
    trans = np.array([0.0, 0.1, 2.0 * math.sin(0.05), math.hypot(d[0], d[1])])
    assert result.trans_mean == pytest.approx(trans.mean(), abs=1e-12)


def test_time_offset_shifts_the_trajectory_onto_the_relations_clock() -> None:
    times, poses = evaluation.parse_trajectory(TRAJECTORY.splitlines())
    relations = evaluation.parse_relations(RELATIONS.splitlines())
    shifted = evaluation.relation_error(times - 100.0, poses, relations, time_offset=100.0,
                                        exact_only=True)
    assert shifted.relations == 3
    assert shifted.trans_mean == pytest.approx(_score(exact_only=True).trans_mean)


def test_no_matching_stamp_is_an_error() -> None:
    times, poses = evaluation.parse_trajectory(TRAJECTORY.splitlines())
    relations = evaluation.parse_relations(["5 6 0 0 0 0 0 0"])
    with pytest.raises(RelationsError):
        evaluation.relation_error(times, poses, relations, exact_only=True)


@pytest.mark.parametrize("text", ["1 2 3", "a b c d", ""])
def test_a_malformed_trajectory_is_an_error(text: str) -> None:
    with pytest.raises(RelationsError):
        evaluation.parse_trajectory([text])
