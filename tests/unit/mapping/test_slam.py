"""SLAM end to end on a log the simulator records with exact ground truth (demo floor 1)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

from polynav.geometry import Pose2D
from polynav.mapping import evaluation, logs
from polynav.mapping.config import SlamConfig
from polynav.mapping.slam import Slam, replay
from polynav.robot.sim import recording
from polynav.worlds import load_world, tours


@pytest.fixture(scope="module")
def run() -> tuple[recording.Recording, logs.SensorLog, Slam]:
    rec = recording.record(load_world("demo"), seed=3, scan_every=5)
    sensor_log = logs.parse_carmen(rec.lines)
    return rec, sensor_log, replay(sensor_log, SlamConfig())


def _poses(poses: list[Pose2D]) -> np.ndarray:
    return np.array([[p.x, p.y, p.theta] for p in poses])


def _errors(rec: recording.Recording, sensor_log: logs.SensorLog,
            poses: np.ndarray) -> tuple[float, float]:
    lines = recording.relations_from_truth(rec.truth)
    times = np.array([s.stamp for s in sensor_log.scans])
    everything = evaluation.parse_relations(lines)
    loops = evaluation.parse_relations(lines[len(rec.truth) - 1:])
    return (evaluation.relation_error(times, poses, everything, exact_only=True).trans_mean,
            evaluation.relation_error(times, poses, loops, exact_only=True).trans_mean)


def test_recording_keeps_one_truth_pose_per_scan_with_the_same_stamps(run) -> None:
    rec, sensor_log, _ = run
    assert [s.stamp_text for s in sensor_log.scans] == [t for t, _ in rec.truth]
    assert sensor_log.skipped_lines == 0 and sensor_log.has_odometry
    assert len(rec.truth) > 200


def test_slam_closes_the_loop_of_demo_floor_1(run) -> None:
    rec, sensor_log, slam = run
    overall, loops = _errors(rec, sensor_log, _poses(slam.trajectory()))
    odometry = _poses([s.odom for s in sensor_log.scans])
    _, odometry_loops = _errors(rec, sensor_log, odometry)
    assert slam.loop_closures > 0
    assert overall < 0.05
    assert loops < 0.05
    assert loops < 0.5 * odometry_loops  # the loop closures, not the odometry, did it


def test_the_map_walls_lie_on_the_true_walls(run) -> None:
    rec, _, slam = run
    truth = load_world("demo").floor("floor1").map
    grid = slam.render_map()
    # The map frame is the first scan's odometry frame, which starts at (0, 0, 0) where the
    # simulated base was created: the walls go over to the world through that pose.
    walls = np.argwhere(grid.data == 100)[:, ::-1]
    local = grid.info.cells_to_world(walls)
    start = rec.odometry_origin
    c, s = math.cos(start.theta), math.sin(start.theta)
    world = np.column_stack((start.x + c * local[:, 0] - s * local[:, 1],
                             start.y + s * local[:, 0] + c * local[:, 1]))
    cells = truth.info.world_to_cells(world)
    near = ndimage.distance_transform_edt(~truth.occupied())
    inside = ((cells[:, 0] >= 0) & (cells[:, 0] < truth.info.width)
              & (cells[:, 1] >= 0) & (cells[:, 1] < truth.info.height))
    assert inside.mean() > 0.99
    distance = near[cells[inside, 1], cells[inside, 0]]
    # 0.875 within 0.1 m today: far walls seen through doors carry the heading error out to
    # 0.2 m. The exploration target (issue 9: 95 % within one cell) is still ahead.
    assert (distance <= 2.0).mean() > 0.85


def test_scans_between_nodes_follow_odometry_from_the_last_node() -> None:
    slam = Slam(SlamConfig())
    angles = np.linspace(-math.pi, math.pi, 90, endpoint=False)
    ranges = np.full(90, 3.0)
    first = slam.add_scan(Pose2D(1.0, 2.0, 0.5), ranges, angles, 0.0)
    second = slam.add_scan(Pose2D(1.0, 2.0, 0.5).compose(Pose2D(0.02, 0.0, 0.01)), ranges,
                           angles, 0.1)
    assert slam.node_count == 1
    assert (first.x, first.y, first.theta) == (1.0, 2.0, 0.5)
    assert (second.x, second.y) == pytest.approx(
        (1.0 + 0.02 * math.cos(0.5), 2.0 + 0.02 * math.sin(0.5)))
    assert len(slam.trajectory()) == 2


def test_a_row_of_identical_rooms_does_not_fool_the_loop_search(data_dir: Path) -> None:
    # MovingAI room-32-32-4: 3 m rooms repeating every 4 m. A loop search 4 m wide finds the
    # next room as good a fit as the right one (0.84 m error on this tour); sized by the drift
    # since the last loop closure, it looks only as far as the robot can have drifted.
    tour = tours.plan_tour(data_dir / "movingai" / "room-32-32-4.map", stops=3, seed=1)
    rec = recording.record(tour.world, tour.waypoints, seed=1, scan_every=5, time_limit=300.0)
    sensor_log = logs.parse_carmen(rec.lines)
    slam = replay(sensor_log, SlamConfig())
    assert slam.loop_closures > 0
    everything, loops = _errors(rec, sensor_log, _poses(slam.trajectory()))
    assert everything < 0.01 and loops < 0.02


def test_a_map_rendered_as_it_grows_is_the_map_rendered_once(run) -> None:
    """The live map is rendered at each replan of an exploration, only the new nodes inserted
    while the graph stays as it was: it must be the very map one render of the same nodes
    gives, loop closures (which move earlier nodes) included."""
    _, sensor_log, _ = run
    growing, once = Slam(SlamConfig()), Slam(SlamConfig())
    renders = 0
    # Past the first loop closures (the graph is solved again at scans 134 and 154), then
    # a few renders on the solved graph.
    for scan in sensor_log.scans[:165]:
        for slam in (growing, once):
            slam.add_scan(scan.odom, scan.ranges, scan.angles, scan.stamp,
                          sensor_pose=scan.sensor_pose)
        if growing.node_count % 3 == 0:
            growing.render_map()
            renders += 1
    assert growing.loop_closures > 0 and renders > 20

    def same() -> bool:
        a, b = growing.render_map(), once.render_map()
        return a.info == b.info and np.array_equal(a.data, b.data)

    assert same()
    growing.finish()
    once.finish()
    assert same()
