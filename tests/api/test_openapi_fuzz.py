"""The native API against its own OpenAPI document, fuzzed by Schemathesis in process.

Schemathesis reads ``/openapi.json`` from the ASGI app and, for every operation, sends requests
the document allows (they must be accepted or refused only as declared) and requests it forbids
(they must be refused with a 4xx), in its three phases: the document's examples (which name the
demo site's cars, maps and points, polynav/api/examples.py), the coverage of each schema's edges,
and fuzzing. Then it chains operations statefully along the document's links and those it infers
(a listed car requested, navigation started at a listed point, a point created, found, renamed,
deleted). Every check runs: no 5xx, only declared status codes, content types, headers
and bodies that match the document, 405 with ``Allow`` for undeclared methods, and so on.

The app wraps the FakeRuntime around a real site store seeded with the demo world. The WebSocket
route is the only one left out: OpenAPI cannot describe it, so it is not in the document.
Examples are bounded and derandomized, so a run is the same on every machine.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any, cast

import pytest
import schemathesis
from hypothesis import settings
from hypothesis import strategies as st
from pydantic import TypeAdapter, ValidationError
from schemathesis import Case

from polynav.api import ApiConfig, create_app
from polynav.api.schemas import Name
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from tests.api.fakes import FakeRuntime

EXAMPLES_PER_OPERATION = 50
STATEFUL_EXAMPLES = 40
DEMO_MAPS = ("floor1", "floor2")
DEMO = load_world("demo")


def _hypothesis_settings(max_examples: int, **more: int) -> settings:
    return settings(
        max_examples=max_examples,
        derandomize=True,  # the same examples on every run and machine
        deadline=None,  # the machine is shared: time is not the property under test
        database=None,
        **more,
    )


class _Unbound:
    """Stands in for the runtime and the store until the ``site`` fixture binds the app to real
    ones: pytest collects the operations from the document before any tmp_path exists, and the
    document does not depend on either (the routes read them from ``app.state`` per request).

    (``schemathesis.pytest.from_fixture`` would load the schema from a fixture instead, but it
    sets ``Node._nodeid``, which pytest 9.2 no longer has.)"""


APP = create_app(
    cast(RobotRuntime, _Unbound()), ApiConfig(port=0), store=cast(SiteStore, _Unbound())
)
schema = schemathesis.openapi.from_asgi("/openapi.json", APP)
schema.config.generation.update(max_examples=EXAMPLES_PER_OPERATION, deterministic=True)
_NAME = TypeAdapter(Name)


@schema.hook
def flatmap_body(context: object, body: object) -> st.SearchStrategy[object]:
    """Often put one of the demo's maps where a body names a map, so that points get created
    and navigation starts: a drawn name is almost never a map, and the stateful chains start
    from a created point. Only a valid name is swapped, so a body meant to be refused stays so."""
    if not isinstance(body, dict) or not isinstance(body.get("map"), str):
        return st.just(body)
    try:
        _NAME.validate_python(body["map"])
    except ValidationError:
        return st.just(body)
    return st.sampled_from((body["map"], *DEMO_MAPS)).map(lambda name: {**body, "map": name})


class _Site:
    """The site the app serves: a real store seeded with the demo world, under tmp_path, with
    the FakeRuntime around it. ``fresh()`` replaces both, so that every stateful example starts
    from the same site (Hypothesis replays an example and needs the same answers)."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self.opened = 0
        self.store: SiteStore | None = None

    def fresh(self) -> FakeRuntime:
        self.close()
        self.opened += 1
        self.store = SiteStore.open(self.root / f"site{self.opened}", seed_world=DEMO)
        runtime = FakeRuntime(self.store)
        APP.state.runtime, APP.state.store = runtime, self.store
        return runtime

    def close(self) -> None:
        if self.store is not None:
            self.store.close()
            self.store = None


SITE: _Site | None = None


@pytest.fixture(scope="module", autouse=True)
def site(tmp_path_factory: pytest.TempPathFactory) -> Iterator[_Site]:
    """One site for the per-operation tests (state carries from one operation to the next, so
    a goal may meet a robot that a started navigation left navigating), fresh ones per stateful
    example."""
    global SITE
    SITE = _Site(tmp_path_factory.mktemp("fuzz"))
    SITE.fresh()
    yield SITE
    SITE.close()
    SITE = None


@schema.parametrize()
@_hypothesis_settings(EXAMPLES_PER_OPERATION)
def test_every_operation_keeps_its_contract(case: Case) -> None:
    case.call_and_validate()


class ChainedOperations(schema.as_state_machine()):  # type: ignore[misc]
    """Operations chained along the document's links and those Schemathesis infers (a point
    created, then read, renamed, deleted; a listed car requested; navigation started at a listed
    point, then a goal), each example on a fresh site. Every answer is kept in ``ANSWERS``."""

    def setup(self) -> None:
        assert SITE is not None, "the site fixture binds the app first"
        SITE.fresh()

    def after_call(self, response: Any, case: Case) -> None:
        super().after_call(response, case)
        ANSWERS.append((case.operation.definition.raw["operationId"], response.status_code))


ANSWERS: list[tuple[str, int]] = []
# Operations on a resource of the site that the chains must reach with a 2xx: a lift car through
# GET /api/lifts, navigation through a listed or created point. Which chains the state machine
# walks depends on what ran before it in the process (its link calibration), so only the chains
# it takes alone as well are required: a point read by name (its links are in the document) is
# reached for sure by the examples test (test_openapi_examples.py), not required here.
REACHED_BY_LINKS = {"request_lift", "start_navigation"}


def test_chained_operations_keep_their_contract_and_reach_the_resources() -> None:
    ANSWERS.clear()
    ChainedOperations.run(settings=_hypothesis_settings(STATEFUL_EXAMPLES,
                                                        stateful_step_count=8))
    succeeded = {operation for operation, status in ANSWERS if 200 <= status < 300}
    assert REACHED_BY_LINKS - succeeded == set(), sorted(succeeded)
