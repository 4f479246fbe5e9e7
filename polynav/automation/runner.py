"""Running automation programs: one process each, limited, talking to the robot by actions.

Automations are off unless the runtime is configured for them (``RuntimeConfig.automations``):
a program is code a user sends over the network. When on, :meth:`AutomationRunner.start` writes
the program into its own folder under the data directory and starts
:mod:`polynav.automation.child` in a new interpreter, isolated from the environment and from
site-packages (it cannot import polynav), with its CPU time and memory capped (the child sets
its own limits before the program runs) and a wall-clock limit kept here. Each request the
program makes is one action of the task engine's catalogue, run as a one-action task of the
robot (so it pre-empts and is pre-empted like any task), and answered with how it ended.

A run ends ``COMPLETE`` when the program returns, ``ERROR`` when it raised, was killed at a
limit, or the runner was closed; the reason names which. The runs and the tail of each
program's log are kept for reading.
"""

from __future__ import annotations

import json
import logging
import signal
import subprocess
import sys
import threading
import time
import uuid
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

from polynav.errors import Conflict, InvalidRequest, NotFound, PolynavError

log = logging.getLogger(__name__)

CHILD = Path(__file__).with_name("child.py")
MAX_PROGRAM = 256 * 1024  # [bytes]
MAX_LINE = 64 * 1024  # [bytes] of one request
LOG_LINES = 200
POLL = 0.02  # [s] of wall time between looks at a running action


@dataclass(frozen=True, slots=True)
class AutomationLimits:
    """What one program may use: wall time and CPU time [s], memory [bytes]."""

    wall_seconds: float = 600.0
    cpu_seconds: int = 60
    memory_bytes: int = 512 * 1024 * 1024


class TaskDesk(Protocol):
    """The part of ``runtime.tasks`` the runner uses."""

    def create(self, spec: Mapping[str, Any], *, owner: str = ..., kind: str = ...,
               temporary: bool = ..., start: bool = ...) -> dict[str, Any]: ...

    def get(self, task_id: str) -> dict[str, Any]: ...

    def cancel(self, task_id: str, node_id: str | None = None) -> dict[str, Any]: ...


@dataclass
class AutomationRun:
    """One run of a program."""

    automation_id: str
    id: str = field(default_factory=lambda: str(uuid.uuid4()))
    state: str = "WORKING"
    reason: str = ""
    actions: int = 0
    log: deque[str] = field(default_factory=lambda: deque(maxlen=LOG_LINES))

    def describe(self) -> dict[str, Any]:
        return {"id": self.id, "automation_id": self.automation_id, "state": self.state,
                "reason": self.reason, "actions": self.actions, "log": list(self.log)}


class AutomationRunner:
    """Starts and watches automation processes."""

    def __init__(self, tasks: TaskDesk, folder: Path | None, *, enabled: bool,
                 limits: AutomationLimits | None = None,
                 on_end: Callable[[AutomationRun], None] | None = None) -> None:
        self._tasks = tasks
        self._folder = folder
        self.enabled = enabled
        self.limits = limits or AutomationLimits()
        self._on_end = on_end
        self._runs: dict[str, AutomationRun] = {}
        self._procs: dict[str, subprocess.Popen[str]] = {}
        self._lock = threading.Lock()

    def runs(self, automation_id: str | None = None) -> list[dict[str, Any]]:
        with self._lock:
            return [r.describe() for r in self._runs.values()
                    if automation_id is None or r.automation_id == automation_id]

    def run(self, run_id: str) -> dict[str, Any]:
        with self._lock:
            found = self._runs.get(run_id)
        if found is None:
            raise NotFound("automation run", run_id)
        return found.describe()

    def start(self, automation_id: str, program: str) -> dict[str, Any]:
        """Run ``program`` for automation ``automation_id``; the run.

        Raises:
            Conflict: automations are off, no data directory, or this automation runs already.
            InvalidRequest: a program too large, or not text.
        """
        if not self.enabled:
            raise Conflict("automation tasks are off: start polynav with automations on "
                           "(runtime config automations: true)")
        if self._folder is None:
            raise Conflict("automation tasks need a data directory")
        if not isinstance(program, str) or len(program.encode()) > MAX_PROGRAM:
            raise InvalidRequest("py", f"must be a program of at most {MAX_PROGRAM} bytes")
        safe = "".join(c for c in automation_id if c.isalnum() or c in "-_")[:64]
        if not safe:
            raise InvalidRequest("id", "an automation id of letters, digits, '-' or '_'")
        with self._lock:
            if any(r.automation_id == automation_id and r.state == "WORKING"
                   for r in self._runs.values()):
                raise Conflict(f"automation {automation_id} runs already")
            run = AutomationRun(automation_id)
            self._runs[run.id] = run
        folder = self._folder / safe
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "program.py").write_text(program, encoding="utf-8")
        proc = subprocess.Popen(
            [sys.executable, "-I", "-S", str(CHILD), str(folder),
             str(self.limits.cpu_seconds), str(self.limits.memory_bytes)],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
            cwd=folder, text=True, encoding="utf-8", errors="replace",
            start_new_session=True)
        self._procs[run.id] = proc
        threading.Thread(target=self._serve, args=(run, proc), daemon=True,
                         name=f"automation-{safe}").start()
        log.info("automation %s: run %s started (pid %d)", automation_id, run.id, proc.pid)
        return run.describe()

    def stop(self, run_id: str) -> dict[str, Any]:
        """Kill a run; it ends ``CANCELLED``."""
        with self._lock:
            run = self._runs.get(run_id)
        if run is None:
            raise NotFound("automation run", run_id)
        proc = self._procs.get(run_id)
        if proc is not None and proc.poll() is None:
            run.reason = "stopped"
            proc.kill()
        return run.describe()

    def close(self) -> None:
        """Kill every run (the server stops)."""
        for run_id, proc in list(self._procs.items()):
            if proc.poll() is None:
                self._runs[run_id].reason = "polynav stopped"
                proc.kill()

    # -- the run's threads ---------------------------------------------------------------------

    def _read_log(self, run: AutomationRun, proc: subprocess.Popen[str]) -> None:
        assert proc.stderr is not None
        with proc.stderr:
            for line in proc.stderr:
                run.log.append(line.rstrip("\n")[:1000])

    def _serve(self, run: AutomationRun, proc: subprocess.Popen[str]) -> None:
        assert proc.stdout is not None and proc.stdin is not None
        reader = threading.Thread(target=self._read_log, args=(run, proc), daemon=True)
        reader.start()
        deadline = time.monotonic() + self.limits.wall_seconds
        timer = threading.Timer(self.limits.wall_seconds, self._overtime, (run, proc))
        timer.daemon = True
        timer.start()
        try:
            for line in proc.stdout:
                if len(line) > MAX_LINE:
                    reply: dict[str, Any] = {"error": f"a request is at most {MAX_LINE} bytes"}
                else:
                    reply = self._answer(run, line, deadline)
                try:
                    proc.stdin.write(json.dumps(reply) + "\n")
                    proc.stdin.flush()
                except (BrokenPipeError, ValueError):
                    break
        finally:
            timer.cancel()
            code = proc.wait()
            reader.join(timeout=2.0)  # the last lines name why it ended
            for pipe in (proc.stdin, proc.stdout):
                try:
                    pipe.close()
                except OSError:
                    pass  # the child closed its end first
            self._ended(run, code)

    def _answer(self, run: AutomationRun, line: str, deadline: float) -> dict[str, Any]:
        try:
            request = json.loads(line)
            kind, params = request["type"], request.get("params", {})
            if not isinstance(kind, str) or not isinstance(params, dict):
                raise TypeError("type must be a string and params an object")
        except (ValueError, KeyError, TypeError) as exc:
            return {"error": f"bad request: {exc}"}
        run.actions += 1
        try:
            task = self._tasks.create({"name": f"automation {run.automation_id}",
                                       "sub_tasks": [{"type": kind, **params}]},
                                      owner="automation", kind="automation", temporary=True,
                                      start=True)
        except PolynavError as exc:
            return {"error": str(exc)}
        while True:
            snap = self._tasks.get(task["id"])
            if snap["state"] not in ("WAITTING", "WORKING", "PAUSED"):
                leaf = snap["tree"]["children"][0]
                return {"state": leaf["state"], "result": leaf["result"] or snap["note"],
                        "blackboard": snap["blackboard"]}
            if time.monotonic() > deadline:
                self._tasks.cancel(task["id"])
                return {"error": "wall time limit"}
            time.sleep(POLL)

    def _overtime(self, run: AutomationRun, proc: subprocess.Popen[str]) -> None:
        if proc.poll() is None:
            run.reason = f"killed: over its wall time limit of {self.limits.wall_seconds:g} s"
            proc.kill()

    def _ended(self, run: AutomationRun, code: int) -> None:
        if code == 0:
            run.state = "COMPLETE"
        elif run.reason == "stopped":
            run.state = "CANCELLED"
        else:
            run.state = "ERROR"
            if not run.reason:
                run.reason = _why(code, run)
        self._procs.pop(run.id, None)
        log.info("automation %s: run %s ended %s %s", run.automation_id, run.id, run.state,
                 run.reason)
        if self._on_end is not None:
            self._on_end(run)


def _why(code: int, run: AutomationRun) -> str:
    if code == -signal.SIGXCPU or code == -signal.SIGKILL:
        return "killed: over its CPU time limit"
    last = next((line for line in reversed(run.log) if line.strip()), "")
    if "MemoryError" in last:
        return "killed: over its memory limit"
    return f"failed (exit {code}): {last}" if last else f"failed (exit {code})"
