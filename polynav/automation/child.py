"""The process an automation task runs in (started by :mod:`polynav.automation.runner`).

Run as ``python -I -S child.py FOLDER``: isolated from the environment and from site-packages,
so the program cannot import polynav (nor anything installed beside it), only the standard
library. The program is ``FOLDER/program.py``; it runs with ``FOLDER`` as its working directory
and may write only there: an audit hook refuses opening for writing, renaming, removing or
creating outside it, starting processes, and opening sockets (the robot is reached through the
``robot`` object, not the network). Memory and CPU time are capped by the parent.

The program sees one global, ``robot``; each call is a request to the robot, written as one JSON
line on the channel (the original standard output) and answered by one JSON line on standard
input. ``print`` goes to the log (standard error).

This file imports nothing of polynav: it must run where polynav cannot be imported.
"""

import json
import os
import resource
import sys
from typing import Any

FOLDER = os.path.realpath(sys.argv[1])
CPU_SECONDS = int(sys.argv[2])
MEMORY_BYTES = int(sys.argv[3])
_channel = os.fdopen(os.dup(1), "w", encoding="utf-8", buffering=1)
os.dup2(2, 1)  # print() goes to the log
sys.stdout = sys.stderr


def _inside(path: Any) -> bool:
    try:
        real = os.path.realpath(os.fsdecode(path))
    except (TypeError, ValueError):
        return False
    return real == FOLDER or real.startswith(FOLDER + os.sep)


_WRITE_FLAGS = os.O_WRONLY | os.O_RDWR | os.O_APPEND | os.O_CREAT | os.O_TRUNC
_FORBIDDEN = ("subprocess.Popen", "os.system", "os.exec", "os.posix_spawn", "os.fork",
              "os.spawn", "socket.connect", "socket.bind", "ctypes.dlopen", "os.kill")


def _audit(event: str, args: tuple[Any, ...]) -> None:
    if event == "open":
        path, mode, flags = args
        if isinstance(path, int):
            return
        writing = (isinstance(mode, str) and any(c in mode for c in "wax+")) or (
            isinstance(flags, int) and flags & _WRITE_FLAGS)
        if writing and not _inside(path):
            raise PermissionError(f"automation may write only in its folder, not {path}")
    elif event in ("os.rename", "os.remove", "os.rmdir", "os.mkdir", "os.symlink",
                   "os.link", "shutil.rmtree", "os.chmod", "os.truncate"):
        for path in args[:2]:
            if isinstance(path, (str, bytes, os.PathLike)) and not _inside(path):
                raise PermissionError("automation may change files only in its folder")
    elif event.startswith(_FORBIDDEN):
        raise PermissionError(f"automation may not use {event}")
    elif event == "import" and args and str(args[0]).split(".")[0] == "polynav":
        raise ImportError("automation may not import polynav: use the robot object")


class RobotError(Exception):
    """The robot refused a request (bad parameters, an unknown action)."""


class Robot:
    """The robot, for an automation program: every method waits until the action ended and
    returns ``{"state", "result", "blackboard"}`` (``state`` is the action's final state:
    ``COMPLETE``, ``FAIL``, ``ERROR`` or ``CANCELLED``)."""

    def __init__(self) -> None:
        self._seq = 0

    def run(self, type: str, **params: Any) -> dict[str, Any]:
        """Run one action of the task engine's catalogue (``nav_action``, ``tts_action``...)."""
        self._seq += 1
        _channel.write(json.dumps({"id": self._seq, "op": "action", "type": type,
                                   "params": params}) + "\n")
        line = sys.stdin.readline()
        if not line:
            raise SystemExit("the robot closed the channel")
        reply: dict[str, Any] = json.loads(line)
        if reply.get("error"):
            raise RobotError(reply["error"])
        return reply

    def go(self, x: float | None = None, y: float | None = None, theta: float = 0.0,
           point: str | None = None, map: str | None = None) -> dict[str, Any]:
        params: dict[str, Any] = {"theta": theta} if point is None else {"point": point}
        if point is None:
            params.update(x=x, y=y)
        if map is not None:
            params["map"] = map
        return self.run("nav_action", **params)

    def say(self, text: str) -> dict[str, Any]:
        return self.run("tts_action", text=text)

    def sleep(self, seconds: float) -> dict[str, Any]:
        return self.run("sleep_action", wait_time=seconds)

    def io(self, port: int, level: int) -> dict[str, Any]:
        return self.run("io_action", port=str(port), level=str(level))

    def wait_trigger(self, timeout: float = 0) -> dict[str, Any]:
        return self.run("wait_req_action", timeout=timeout)


def main() -> None:
    resource.setrlimit(resource.RLIMIT_CPU, (CPU_SECONDS, CPU_SECONDS + 1))
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_BYTES, MEMORY_BYTES))
    sys.addaudithook(_audit)
    os.chdir(FOLDER)
    with open(os.path.join(FOLDER, "program.py"), encoding="utf-8") as f:
        source = f.read()
    code = compile(source, "program.py", "exec")
    exec(code, {"__name__": "__main__", "robot": Robot(), "RobotError": RobotError})


if __name__ == "__main__":
    main()
