"""The OpenAPI document's examples and links: requests that name resources a site really has.

An operation on an existing resource (a lift car, a map, a point, a task) answers 404 to a name
drawn at random, so a reader of the document, or a tool that tries its examples (Schemathesis's
examples phase), learns nothing from it. The examples here name the built-in demo site's
resources (``polynav run`` serves it; ``polynav/worlds/demo/world.yaml``): its maps ``floor1`` to
``floor3``, its points, its cars ``lift_1`` and ``lift_2``. The links say where a response hands a
name on to the next request (a listed car to its request, a created task to its start), which
is how a client, and Schemathesis's stateful phase, reaches resources made at run time (task,
schedule and job ids).

Only the demo's names are used, so tests/api/test_openapi_examples.py can prove that each
example answers 2xx on the demo site.
"""

from __future__ import annotations

from typing import Any

from fastapi.openapi.models import Example

# The demo site's resources the examples name (polynav/worlds/demo/world.yaml).
DEMO_MAP = "floor1"
DEMO_FLOOR = "floor1"
DEMO_CAR = "lift_1"
DEMO_CAR_FLOOR = "floor2"  # a floor lift_1 serves
START_POINT = "initial"  # where the demo robot starts on floor1
GOAL_POINT = "lobby"
MOVED_POINT = "kitchen"
REMOVED_POINT = "print_room"
NEW_POINT = "reception"
NEW_MAP = "floor1_survey"


def examples(**named: Any) -> dict[str, Example]:
    """``openapi_examples`` from ``summary=value`` pairs: each keyword is the example's name,
    its summary the name with spaces."""
    return {name: Example(summary=name.replace("_", " "), value=value)
            for name, value in named.items()}


def one(summary: str, value: Any) -> dict[str, Example]:
    """A single named example (a path or query parameter's)."""
    return {summary.replace(" ", "_"): Example(summary=summary, value=value)}


def links(**named: dict[str, Any]) -> dict[str, Any]:
    """A response's ``links`` (OpenAPI 3 Link Objects by name), for ``responses=``."""
    return {"links": named}


def link(operation_id: str, *, parameters: dict[str, str] | None = None,
         body: dict[str, Any] | None = None, description: str = "") -> dict[str, Any]:
    """One Link Object: the operation it leads to, its parameters and body as runtime
    expressions (``$response.body#/id``)."""
    out: dict[str, Any] = {"operationId": operation_id}
    if parameters:
        out["parameters"] = parameters
    if body is not None:
        out["requestBody"] = body
    if description:
        out["description"] = description
    return out


NAP_TASK = {"name": "nap", "sub_tasks": [{"type": "sleep_action", "wait_time": 5.0}]}
