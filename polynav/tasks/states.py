"""Node states of a task tree, spelled as the vendors spell them on the wire.

Galileo's task and behavior-tree documents name seven states (galileo-tasks-bt-ws §2.2),
misspelling ``WAITTING`` included; the engine uses them as they are so that no dialect has to
translate state names. ``FAIL`` is a normal result a parent branches on; ``ERROR`` is a fault
that stops the whole tree.
"""

from __future__ import annotations

import enum


class NodeState(enum.Enum):
    """Where a node of a task tree is."""

    WAITTING = "WAITTING"
    WORKING = "WORKING"
    PAUSED = "PAUSED"
    CANCELLED = "CANCELLED"
    ERROR = "ERROR"
    COMPLETE = "COMPLETE"
    FAIL = "FAIL"

    @property
    def final(self) -> bool:
        return self in FINAL

    @property
    def active(self) -> bool:
        """Started and not ended (running or paused)."""
        return self in (NodeState.WORKING, NodeState.PAUSED)


FINAL = frozenset({NodeState.CANCELLED, NodeState.ERROR, NodeState.COMPLETE, NodeState.FAIL})
