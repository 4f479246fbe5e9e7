"""``POST /navigation/coverage_path`` over real HTTP (galileo-http-b E65)."""

from __future__ import annotations

from tests.protocols.galileo.conftest import Harness

COVERED = {
    "POST /api/v1/navigation/coverage_path": "test_coverage_path_of_the_documented_example",
}

EXAMPLE = {
    "swath_angle": -3, "op_width": 0.5, "turn_radius": 0.5, "headland_width": 0.5,
    "border": [[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0], [0, 0, 0]],
    "holes": [[[2, 2, 0], [2, 3, 0], [3, 3, 0], [3, 2, 0], [2, 2, 0]]],
}


def test_coverage_path_of_the_documented_example(galileo: Harness) -> None:
    body = galileo.ok("POST", "/navigation/coverage_path", json=EXAMPLE)
    assert body["status"] == "ok"
    path = body["path"]
    assert all(len(p) == 3 and p[2] == 0 for p in path)
    xs, ys = [p[0] for p in path], [p[1] for p in path]
    assert min(xs) >= 0.5 - 1e-6 and max(xs) <= 9.5 + 1e-6  # the headland is kept
    assert min(ys) >= 0.5 - 1e-6 and max(ys) <= 9.5 + 1e-6
    assert not any(2 < x < 3 and 2 < y < 3 for x, y, _ in path)  # the hole is left out
    lanes = sorted({round(y, 6) for y in ys}) if len({round(x, 6) for x in xs}) > 2 else []
    assert lanes and all(abs(b - a - 0.5) < 1e-6 for a, b in zip(lanes, lanes[1:], strict=False))
    manual = galileo.ok("POST", "/navigation/coverage_path",
                        json={**EXAMPLE, "swath_angle": 90, "holes": []})["path"]
    assert abs(manual[0][0] - manual[1][0]) < 1e-6  # lanes along y


def test_coverage_path_bad_input(galileo: Harness) -> None:
    for bad in ({**EXAMPLE, "swath_angle": 200}, {**EXAMPLE, "op_width": 0},
                {**EXAMPLE, "border": [[0, 0, 0], [1, 1, 0]]},
                {**EXAMPLE, "border": "square"}, {**EXAMPLE, "turn_radius": -1},
                {k: v for k, v in EXAMPLE.items() if k != "op_width"},
                {**EXAMPLE, "holes": [[[0, 0, 0]]]}):
        response = galileo.post("/navigation/coverage_path", bad)
        assert response.status_code == 400, (bad, response.text)
        assert response.json()["status"] == "error"
