"""The native API asking for a login, against its own OpenAPI document, fuzzed by Schemathesis.

As tests/api/test_openapi_fuzz.py, with the gate on: each request carries a valid operator
token, and every check runs, ``ignored_auth`` included: for each operation it repeats a
successful request without the token and with a forged one and expects them refused, so the
document's security is proven enforced, operation by operation. Fewer examples than the open
API's run: the routes behind the gate are the same and fuzzed there.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import cast

import pytest
import schemathesis
from hypothesis import settings
from schemathesis import Case

from polynav.api import ApiConfig, create_app
from polynav.api.auth_passwords import new_token, token_hash
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from tests.api.auth_site import add_users
from tests.api.fakes import FakeRuntime

EXAMPLES_PER_OPERATION = 10


class _Unbound:
    """Stands in for the runtime and the store until the fixture binds real ones (see
    tests/api/test_openapi_fuzz.py)."""


APP = create_app(cast(RobotRuntime, _Unbound()), ApiConfig(port=0, auth=True),
                 store=cast(SiteStore, _Unbound()))
schema = schemathesis.openapi.from_asgi("/openapi.json", APP)
schema.config.generation.update(max_examples=EXAMPLES_PER_OPERATION, deterministic=True)
STORE: list[SiteStore] = []


@pytest.fixture(scope="module", autouse=True)
def site(tmp_path_factory: pytest.TempPathFactory) -> Iterator[SiteStore]:
    store = SiteStore.open(tmp_path_factory.mktemp("fuzz") / "data",
                           seed_world=load_world("demo"))
    add_users(store)
    APP.state.runtime, APP.state.store = FakeRuntime(store), store
    STORE.append(store)
    yield store
    STORE.clear()
    store.close()


def _operator_token() -> str:
    """A fresh operator token per example: one example may log out (revoking its own)."""
    token = new_token()
    STORE[0].add_token(token_hash(token), "olga", 0.0, 4.0e9)
    return token


@schema.parametrize()
@settings(max_examples=EXAMPLES_PER_OPERATION, derandomize=True, deadline=None, database=None)
def test_every_operation_keeps_its_contract_behind_the_login(case: Case) -> None:
    case.call_and_validate(headers={"Authorization": f"Bearer {_operator_token()}"})
