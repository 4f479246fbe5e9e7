"""The mapping session as the status shows it: what the console shows, the API serves first.

While the robot maps (or a map is being saved) ``GET /api/status`` carries a ``mapping`` object:
whether the map is new or an update of a saved one, how the exploration goes (its stage, the
frontiers its last search left, the targets it reached), how much is mapped, the scans taken,
when it started, and the session's save job. It is built on the loop thread with the rest of
the snapshot, from values the session and the exploration keep (the mapped area is refreshed at
a low rate by the session), so that reading it costs nothing.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from polynav.runtime.mapping_jobs import MappingJob

if TYPE_CHECKING:  # the status module stays light: the snapshot is read by every adapter
    from polynav.runtime.exploration import Exploration
    from polynav.runtime.mapping_session import MappingSession


@dataclass(frozen=True, slots=True)
class MappingStatus:
    """The mapping session at the snapshot's stamp.

    Attributes:
        kind: ``"new"`` (a new map) or ``"update"`` (extending a saved map).
        map: the saved map being updated, ``None`` for a new map.
        exploration: ``"off"`` (driven by hand), ``"exploring"``, ``"returning"`` (no frontier
            left, driving back to where it began) or ``"done"``.
        frontiers_left: frontier clusters the exploration's last search found still worth a
            visit (``None`` before its first search).
        targets_reached: frontiers the exploration drove to and reached.
        mapped_area_m2: known cells (free or occupied) x the cell's area [m²], refreshed about
            once a second of the runtime's clock.
        scans: scans the SLAM took.
        started_at: when mapping started [s, runtime clock].
        job: the session's current or last save job, if it had one.
    """

    kind: str
    map: str | None
    exploration: str
    frontiers_left: int | None
    targets_reached: int
    mapped_area_m2: float
    scans: int
    started_at: float
    job: MappingJob | None = None

    def with_job(self, job: MappingJob | None) -> MappingStatus:
        return replace(self, job=job)

    def to_dict(self) -> dict[str, object]:
        """The status's ``mapping`` object (JSON-ready)."""
        return {
            "kind": self.kind,
            "map": self.map,
            "exploration": self.exploration,
            "frontiers_left": self.frontiers_left,
            "targets_reached": int(self.targets_reached),
            "mapped_area_m2": float(self.mapped_area_m2),
            "scans": int(self.scans),
            "started_at": float(self.started_at),
            "job": None if self.job is None else self.job.to_dict(),
        }


def mapping_status(session: MappingSession, exploration: Exploration | None, now: float,
                   job: MappingJob | None) -> MappingStatus:
    """The status of ``session`` now (refreshing its mapped area when due: call it on the loop
    thread, between ticks)."""
    return MappingStatus(
        kind="update" if session.name is not None else "new",
        map=session.name,
        exploration="off" if exploration is None else exploration.stage.value,
        frontiers_left=None if exploration is None else exploration.frontiers_left,
        targets_reached=0 if exploration is None else exploration.reached,
        mapped_area_m2=session.mapped_area(now),
        scans=session.scans,
        started_at=session.started_at,
        job=job,
    )
