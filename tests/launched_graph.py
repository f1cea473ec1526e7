"""A graph started with ``hawt launch`` from a test as a user would start it: its output read as it comes, the
test waiting on what the plant reports, never on a clock, and nothing left running afterwards."""
import re
import signal
import subprocess
import sys
import threading
import time
from typing import List, Sequence

CLI = [sys.executable, "-m", "hawt_tools.cli"]


def returned_and_ran_on(lines: Sequence[str], reports: int = 2) -> bool:
    """In a graph's output: every contribution the loop assembler lost has returned (the last of its
    contribution_lost / contribution_returned lines is a return), and the plant has printed ``reports`` progress
    lines since (2 s at a report_period of 1 s)."""
    marks = [i for i, line in enumerate(lines) if "contribution_lost: " in line or "contribution_returned: " in line]
    return bool(marks) and "contribution_returned: " in lines[marks[-1]] and \
        sum(bool(re.search(r"\]: t=\d+\.0 s \(", line)) for line in lines[marks[-1]:]) >= reports


def last_sent_step(lines: Sequence[str]) -> int:
    """The plant's last step sent, as it names it when it stops (``stopped: step N (t=...) was the last sent``)."""
    (step,) = [int(m.group(1)) for m in map(re.compile(r"stopped: step (\d+) \(t=").search, lines) if m]
    return step


class LaunchedGraph:
    """``hawt launch ARGUMENTS`` in a child process, as a context manager that stops it if it is still running
    (SIGINT, as Ctrl-C would; killed if it has not ended 60 s later)."""

    def __init__(self, arguments: Sequence[str]) -> None:
        self.process = subprocess.Popen([*CLI, "launch", *arguments], stdout=subprocess.PIPE,
                                        stderr=subprocess.STDOUT, text=True)
        self.lines: List[str] = []
        self._reader = threading.Thread(target=lambda: self.lines.extend(self.process.stdout), daemon=True)
        self._reader.start()

    def __enter__(self) -> "LaunchedGraph":
        return self

    def __exit__(self, *exc) -> None:
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
            try:
                self.process.wait(timeout=60)
            except subprocess.TimeoutExpired:
                self.process.kill()

    def wait_for_line(self, text: str, timeout: float = 180.0, after: int = 0) -> None:
        """Return once a line of the output (from line ``after`` on) contains ``text``; fail, with the output's
        tail, after ``timeout`` s."""
        deadline = time.monotonic() + timeout
        while not any(text in line for line in list(self.lines)[after:]):
            assert time.monotonic() < deadline, f"the graph did not print {text!r}:\n{self.tail()}"
            time.sleep(0.2)

    def wait_until(self, condition, what: str, timeout: float = 180.0) -> None:
        """Return once ``condition()`` holds (checked as the output comes); fail, with the output's tail, after
        ``timeout`` s."""
        deadline = time.monotonic() + timeout
        while not condition():
            assert self.process.poll() is None, f"the graph ended before {what}:\n{self.tail()}"
            assert time.monotonic() < deadline, f"no {what} within {timeout:g} s:\n{self.tail()}"
            time.sleep(0.2)

    def finish(self, timeout: float = 180.0) -> int:
        """Wait for the run to end (the plant ends it) and for its output; its exit code."""
        self.process.wait(timeout=timeout)
        self._reader.join(timeout=10)
        return self.process.returncode

    def tail(self, count: int = 40) -> str:
        return "".join(self.lines[-count:])
