"""Yunji commands that query the site and the navigation stack: accessible points, distance
probes, path lengths, the planned path and lift status (§3.14.5-§3.14.6, §3.20-§3.22)."""

from __future__ import annotations

from polynav.protocols.yunji.commands import Handler

HANDLERS: dict[str, Handler] = {}
