"""How every hawt process hears that it should stop: SIGINT and SIGTERM, handled and then given back."""
import signal
from contextlib import contextmanager
from typing import Callable, Iterator

__all__ = ["stop_signals"]


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
