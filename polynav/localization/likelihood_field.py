"""The likelihood field of a map: how well a lidar endpoint at any cell agrees with the map.

Thrun, Burgard and Fox's likelihood-field sensor model (Probabilistic Robotics, §6.4) scores an
endpoint by its distance to the nearest obstacle, not by ray casting, so a scan costs one lookup
per beam. Everything here is computed once per map and then only read:

- ``distance``: the signed distance [m] from each cell centre to the nearest obstacle *surface*,
  positive in free space and negative inside walls, capped at ``±max_distance``. A lidar return
  lies on the face of the first occupied cell, half a cell from that cell's centre, so the
  surface, not the occupied cell's centre, is where the distance must be zero: interpolated
  bilinearly between cell centres this field is zero exactly on the wall face, which keeps the
  local refinement from pulling the scan half a cell into the walls.
- ``likelihood``: ``exp(-distance² / 2σ²)`` in [0, 1], the table the correlative search sums.

Both come from two exact Euclidean distance transforms (``scipy.ndimage.distance_transform_edt``):
free cells to the nearest occupied cell, and occupied cells to the nearest non-occupied one.
Unknown cells count as not occupied: nothing is known to stop a beam there.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from polynav.maps.map import Map, MapInfo

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True, eq=False)
class LikelihoodField:
    """Signed surface distance and Gaussian likelihood per cell, ``[iy, ix]`` like the map.

    Attributes:
        info: where the grid sits (the map's own :class:`MapInfo`).
        distance: signed distance to the nearest obstacle surface [m], float32, in
            ``[-max_distance, max_distance]``; negative inside obstacles.
        likelihood: ``exp(-distance² / (2 sigma²))``, float32, in [0, 1].
        sigma: standard deviation of the endpoint model [m].
        max_distance: cap of ``distance`` [m]; farther endpoints all count as equally wrong.
    """

    info: MapInfo
    distance: npt.NDArray[np.float32]
    likelihood: npt.NDArray[np.float32]
    sigma: float
    max_distance: float


def build_likelihood_field(
    grid: Map, *, sigma: float = 0.05, max_distance: float = 0.5, occupied_threshold: int = 65,
    centres: bool = False,
) -> LikelihoodField:
    """Precompute the likelihood field of ``grid``.

    Args:
        grid: the occupancy map.
        sigma: standard deviation of the endpoint model [m]; a few centimetres of lidar noise
            plus half a cell of quantisation.
        max_distance: cap of the distance [m]; beyond it an endpoint is simply an outlier (a
            person, a moved chair), and capping keeps it from dragging the match.
        occupied_threshold: map values at or above this are obstacles (ROS ``occupied_thresh``
            0.65 reads as 65).
        centres: measure the distance to the nearest occupied cell's *centre* (unsigned, 0
            there) instead of to the obstacle's surface. For a grid built from scans (SLAM
            submaps) the endpoints that made a wall lie at its cells' centres; with the surface
            distance a one-cell wall scores its cell and both free neighbours alike, and the
            refinement pushes endpoints off the cell centre to either edge, so matches slid by
            a cell at random and the map drifted (0.3 m in 10 s of turning in place).

    Returns:
        The field, sharing ``grid.info``.

    Raises:
        ValueError: ``sigma`` or ``max_distance`` not positive.
    """
    if not sigma > 0.0:
        raise ValueError(f"sigma must be > 0, got {sigma}")
    if not max_distance > 0.0:
        raise ValueError(f"max_distance must be > 0, got {max_distance}")
    res = grid.info.resolution
    occupied = grid.occupied(occupied_threshold)
    half = 0.5 * res
    if occupied.all():
        distance = np.full(occupied.shape, -max_distance)
    elif not occupied.any():
        distance = np.full(occupied.shape, max_distance)
    elif centres:
        distance = np.asarray(ndimage.distance_transform_edt(~occupied), dtype=np.float64) * res
        np.clip(distance, 0.0, max_distance, out=distance)
    else:
        # edt measures, for each non-zero cell, the distance to the nearest zero cell.
        outside = np.asarray(ndimage.distance_transform_edt(~occupied), dtype=np.float64)
        inside = np.asarray(ndimage.distance_transform_edt(occupied), dtype=np.float64)
        distance = np.where(occupied, half - inside * res, outside * res - half)
        np.clip(distance, -max_distance, max_distance, out=distance)
    likelihood = np.exp(-(distance * distance) / (2.0 * sigma * sigma))
    log.debug("likelihood field %dx%d built", grid.info.width, grid.info.height)
    return LikelihoodField(
        info=grid.info,
        distance=np.ascontiguousarray(distance, dtype=np.float32),
        likelihood=np.ascontiguousarray(likelihood, dtype=np.float32),
        sigma=float(sigma),
        max_distance=float(max_distance),
    )


def coarse_likelihood(field: LikelihoodField, cells: int) -> npt.NDArray[np.float32]:
    """The likelihood max-pooled over ``(2 * cells + 1)²`` neighbourhoods, same shape.

    Olson's coarse level (Real-Time Correlative Scan Matching, ICRA 2009, §IV-B): a coarse
    translation step of ``cells`` scored on this table never scores below any fine pose it
    stands for, so the coarse pass does not throw away the true pose for a merely close one.

    Args:
        field: the fine field.
        cells: half-width of the pooling window [cells], ``>= 0``; 0 returns a copy.
    """
    if cells <= 0:
        return field.likelihood.copy()
    size = 2 * int(cells) + 1
    pooled = ndimage.maximum_filter(field.likelihood, size=size, mode="constant", cval=0.0)
    return np.ascontiguousarray(pooled, dtype=np.float32)
