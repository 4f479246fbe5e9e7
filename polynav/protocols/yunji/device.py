"""Yunji commands about the robot as a device: Wi-Fi, LED strip, self-diagnosis, power,
software version/update/restart and shutdown (§3.13, §3.15-§3.19)."""

from __future__ import annotations

from polynav.protocols.yunji.commands import Handler

HANDLERS: dict[str, Handler] = {}
