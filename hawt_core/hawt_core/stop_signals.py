"""How every hawt process hears that it should stop: SIGINT and SIGTERM, handled and then given back, and the death
of the process that started it."""
import os
import signal
from contextlib import contextmanager
from typing import Callable, Iterator

__all__ = ["LAUNCHER_PID", "parent_gone", "stop_signals"]

LAUNCHER_PID = "HAWT_LAUNCHER_PID"
"""Environment variable in which a launcher gives its children its process id (:func:`parent_gone`)."""


@contextmanager
def stop_signals(handler: Callable[..., None]) -> Iterator[None]:
    """Call ``handler(signum, frame)`` on SIGINT and SIGTERM while the block runs; the previous handlers after.

    A process that must finish its work when asked to stop (flush its messages, finish a bag,
    stop its children) installs this instead of letting the default handler end it mid-write.
    """
    previous = {sig: signal.signal(sig, handler) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)


def parent_gone() -> Callable[[], bool]:
    """A check that turns True once the process that started this one has died (this one is re-parented).

    A node or recorder whose launcher was killed (SIGKILL leaves it no time to stop its
    children) stops as it would on SIGTERM, finishing its messages or its bag: the watchdog
    equivalent of ``PR_SET_PDEATHSIG``, which Python can only set in a fork hook that is unsafe
    beside threads and that fires when the forking *thread* ends.

    The launcher names itself in ``HAWT_LAUNCHER_PID``: a launcher killed while this process was
    still starting (before this call) is then seen gone too. The variable is taken out of the
    environment, so that a process this one starts compares with its own parent.
    """
    launcher = os.environ.pop(LAUNCHER_PID, "")
    parent = int(launcher) if launcher.isdigit() else os.getppid()
    return lambda: os.getppid() != parent
