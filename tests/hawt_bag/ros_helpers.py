"""Helpers of the bag tests that drive real processes: hawt child processes and a probe node."""
import os
import signal
import subprocess
import time
from pathlib import Path

from ros_probe import ProbeNode

HERE = Path(__file__).resolve().parent


class Processes:
    """Child processes started by a test, each in its own session; all stopped at the end."""

    def __init__(self, hawt_cli) -> None:
        self.hawt_cli = hawt_cli
        self.started = []

    def hawt(self, *arguments: str, **options) -> subprocess.Popen:
        return self.start([*self.hawt_cli, *arguments], **options)

    def start(self, command, **options) -> subprocess.Popen:
        process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                   start_new_session=True, **options)
        self.started.append(process)
        return process

    @staticmethod
    def stop(process: subprocess.Popen, sig=signal.SIGINT, timeout: float = 30.0) -> tuple[int, str, str]:
        """Send ``sig`` to the process's group and collect its exit code and output."""
        if process.poll() is None:
            os.killpg(process.pid, sig)
        out, err = process.communicate(timeout=timeout)
        return process.returncode, out, err

    def close(self) -> None:
        for process in self.started:
            if process.poll() is None:
                os.killpg(process.pid, signal.SIGKILL)
                process.communicate()


def wait_for_file(path: Path, process: subprocess.Popen, timeout: float = 30.0) -> None:
    deadline = time.monotonic() + timeout
    while not path.exists():
        assert process.poll() is None, f"process ended early: {process.communicate()}"
        assert time.monotonic() < deadline, f"{path} was not created within {timeout} s"
        time.sleep(0.05)


class Probe(ProbeNode):
    """A node in this test process, spun in a thread, to watch the graph and receive messages."""

    def __init__(self) -> None:
        super().__init__("bag_test_probe", background=True)
