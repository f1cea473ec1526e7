"""The recorder of ``hawt launch --record``: started before the graph, watched while it runs, respawned if it dies.

The recorder is hawt_bag's ``record`` executable in a process of its own. A recorder that dies while the graph
runs is reported at once (a ``recorder_lost`` ERROR event and a line) and, unless the recording is optional
(``--record-optional``), started again on the next part of the bag (`hawt_bag.recording_parts.part_path`):
the plant, with ``recorder_required``, holds within its ``recorder_window`` until the new recorder has caught
up, and the new recorder gets back the steps the dead one missed from the publishers' transient-local history.
When the graph has finished, the parts are joined into the bag named on the command line. A recorder that dies
more than `RESPAWNS` times ends the run (the plant would wait for it for ever).
"""
import logging
import os
import signal
import subprocess
import threading
import time
from pathlib import Path
from typing import Callable, List, Optional

from hawt_bag.errors import BagError
from hawt_bag.recording_parts import join_parts, part_path
from hawt_core.stop_signals import LAUNCHER_PID
from hawt_tools.graph_file import package_prefix
from hawt_tools.launcher import describe_exit

__all__ = ["RESPAWNS", "SupervisedRecorder", "start_recorder", "stop_process"]

RESPAWNS = 3
"""How many times a recorder that dies is started again before the run is stopped."""

_START_WAIT = 20.0
"""Wall time [s] a recorder may take to create its bag."""


def start_recorder(path: Path) -> subprocess.Popen:
    """Start the ``record`` executable of hawt_bag on ``path`` and wait until it has created the bag."""
    if path.exists():
        raise BagError(f"{path}: exists; refusing to overwrite a bag (choose another --record name)")
    prefix = package_prefix("hawt_bag")
    executable = Path(prefix or "") / "lib" / "hawt_bag" / "record"
    if prefix is None or not executable.is_file():
        raise RuntimeError("hawt_bag's record executable is not installed (run scripts/setup.sh)")
    recorder = subprocess.Popen([str(executable), "-o", str(path)], stdin=subprocess.DEVNULL,
                                start_new_session=True, env={**os.environ, LAUNCHER_PID: str(os.getpid())})
    deadline = time.monotonic() + _START_WAIT
    while not path.exists():
        if recorder.poll() is not None:
            raise RuntimeError(f"the recorder of {path} exited before recording (exit code {recorder.returncode})")
        if time.monotonic() > deadline:
            stop_process(recorder)
            raise RuntimeError(f"the recorder of {path} did not start within {_START_WAIT:g} s")
        time.sleep(0.02)
    return recorder


def stop_process(process: subprocess.Popen) -> int:
    """Stop the recorder or the view after the graph (SIGINT: the recorder takes what is still arriving, then
    finishes the bag)."""
    for sig, timeout in ((signal.SIGINT, 30.0), (signal.SIGTERM, 5.0), (signal.SIGKILL, 5.0)):
        if process.poll() is not None:
            break
        os.killpg(process.pid, sig)
        try:
            process.wait(timeout)
        except subprocess.TimeoutExpired:
            continue
    return process.wait()


def _report(events: Optional[Callable[[str, int, str, str], None]], namespaces: List[str], line: str) -> None:
    """A ``recorder_lost`` ERROR event in every namespace (published even with no recorder: a respawned one gets it
    from the events' transient-local history)."""
    if events is not None:
        for namespace in namespaces:
            events(namespace, logging.ERROR, "recorder_lost", line)


class SupervisedRecorder:
    """The recorder of a launched graph (see the module notes): `watch` once the graph's events can be published,
    `stop` after the graph; `stop` returns the recorder's exit code (0 once the parts are joined)."""

    def __init__(self, path: Path, optional: bool = False, say: Callable[[str], None] = print) -> None:
        self.path, self.optional, self.say = Path(path), optional, say
        self.parts: List[Path] = [self.path]
        self.process = start_recorder(self.path)
        self.lost: Optional[str] = None
        self._stopping = threading.Event()
        self._thread: Optional[threading.Thread] = None

    def watch(self, events: Optional[Callable[[str, int, str, str], None]], namespaces: List[str]) -> None:
        """Watch the recorder from a thread; a death goes to ``events`` (hawt_tools.launch_events) of every
        namespace."""
        self._thread = threading.Thread(target=self._watch, args=(events, sorted(set(namespaces))), daemon=True)
        self._thread.start()

    def _watch(self, events, namespaces: List[str]) -> None:
        while not self._stopping.wait(0.05):
            code = self.process.poll()
            if code is None:
                continue
            line = f"the recorder of {self.path} died ({describe_exit(code)})"
            if self.optional:
                return self._lose(f"{line}; recording stops here (--record-optional)", events, namespaces)
            if len(self.parts) > RESPAWNS:
                return self._lose(f"{line}; it died {len(self.parts)} times: stopping the graph", events, namespaces)
            part = self._next_part()
            self.say(f"[hawt launch] {line}; respawning it on {part}")
            try:
                self._respawn(part)
            except (BagError, RuntimeError, OSError) as error:
                return self._lose(f"{line}; respawning it failed ({error}): stopping the graph", events, namespaces)
            _report(events, namespaces, f"{line}; respawned on {part} (the plant held until it caught up; the "
                                        f"parts are joined into {self.path} at the end)")

    def _lose(self, line: str, events, namespaces: List[str]) -> None:
        """The recorder is gone for good: say so, and stop the graph unless the recording is optional."""
        self.lost = line
        self.say(f"[hawt launch] {line}")
        _report(events, namespaces, line)
        if not self.optional:
            os.kill(os.getpid(), signal.SIGINT)  # the launcher's own stop: the nodes are stopped as on Ctrl-C

    def _next_part(self) -> Path:
        return part_path(self.path, len(self.parts) + 1)

    def _respawn(self, part: Path) -> None:
        if len(self.parts) == 1:
            self.parts = [part_path(self.path, 1)]
            self.path.rename(self.parts[0])
        self.parts.append(part)
        self.process = start_recorder(part)

    def stop(self) -> int:
        """Stop the watching and the recorder; join the parts into the bag. The recorder's exit code (a recorder
        lost and not respawned: 1)."""
        self._stopping.set()
        if self._thread is not None:
            self._thread.join()
        code = stop_process(self.process)
        if self.lost is not None:
            return code or 1
        if code == 0 and len(self.parts) > 1:
            joined = join_parts(self.parts, self.path)
            for part in self.parts:
                part.unlink()
            self.say(f"[hawt launch] {joined.text()}")
        return code
