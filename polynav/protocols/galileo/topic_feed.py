"""One subscriber's stream of a Galileo topic on the runtime's clock.

Galileo's WebSocket (3547/tcp) and its UDP fast protocol (3547/udp) both serve one topic per
connection from the same table (:data:`~polynav.protocols.galileo.topics.TOPICS`), at the same
rates. This module is the pacing they share, so the two wires cannot drift apart: a topic with a
rate is due every ``1/rate`` s of the runtime's clock (simulated time in simulation; after a jump
of the clock at most one message catches up), a topic without one (``/map``) when its
``changed`` key differs from the one last sent, checked every :data:`CHANGE_CHECK_PERIOD`. The
transport polls :meth:`TopicFeed.take_due` and, when it says so, renders in a worker thread.
"""

from __future__ import annotations

import json
import logging

from polynav.errors import PolynavError
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.topics import Topic

log = logging.getLogger(__name__)

CHANGE_CHECK_PERIOD = 1.0  # [s runtime] how often a topic without a rate looks for a change


class TopicFeed:
    """When the next message of ``topic`` is due for one subscriber, and that message as JSON.

    The first message is due at once. :meth:`take_due` is cheap (call it on the event loop);
    :meth:`render` may block on the runtime (call it in a worker thread).
    """

    def __init__(self, ctx: Context, topic: Topic) -> None:
        self._ctx = ctx
        self.topic = topic
        self._seq = 0
        self._due = ctx.runtime.now()
        self._period = 1.0 / topic.rate if topic.rate > 0 else CHANGE_CHECK_PERIOD
        self._last_key: object = object()

    @property
    def sends(self) -> bool:
        """Whether the topic sends anything (``/cmd_vel`` only takes messages)."""
        return self.topic.render is not None

    def take_due(self) -> bool:
        """Whether a message is due now; if so the next one is scheduled."""
        if self.topic.render is None:
            return False
        now = self._ctx.runtime.now()
        if now + 1e-9 < self._due:
            return False
        self._due = max(self._due + self._period, now)
        if self.topic.changed is None:
            return True
        key = self.topic.changed(self._ctx)
        if key == self._last_key:
            return False
        self._last_key = key
        return True

    def render(self) -> str | None:
        """The due message as JSON text, or ``None`` when there is nothing to send now (no
        source on this robot, powered off); a failure is logged, never raised, so one bad
        message does not end the stream."""
        render = self.topic.render
        if render is None:
            return None
        try:
            message = render(self._ctx, self._seq)
            if message is None:
                return None
            text = json.dumps(message, allow_nan=False)
        except PolynavError as exc:
            log.debug("galileo: %s: nothing to send: %s", self.topic.name, exc)
            return None
        except Exception:  # the one broad except per stream: log, keep serving
            log.error("galileo: %s failed", self.topic.name, exc_info=True)
            return None
        self._seq += 1
        return text
