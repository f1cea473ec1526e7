"""The project's cache on disk: where it is, and how a file gets into it.

``$HAWT_CACHE_DIR`` (default ``~/.cache/hawt``) holds what is computed from inputs and worth keeping between runs:
turbulent wind fields (:func:`hawt_plant.turbulence.cached_turbulence`) and parsed turbine definitions
(:func:`hawt_plant.turbine.load_turbine`), each in a folder of its own and named by a hash of what it was computed
from. The compiled kernels are not here (:mod:`hawt_plant.kernel_cache` says why).
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import IO, Callable

__all__ = ["cache_root", "store"]


def cache_root() -> Path:
    """``$HAWT_CACHE_DIR``, or ``~/.cache/hawt``."""
    return Path(os.environ.get("HAWT_CACHE_DIR") or Path.home() / ".cache" / "hawt")


def store(path: Path, write: Callable[[IO[bytes]], None]) -> None:
    """Write a cache file: ``write`` fills a temporary file in ``path``'s folder (created if missing), which is then
    renamed to ``path``, so that a reader never sees a partial file and concurrent writers of the same file are
    harmless."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile(dir=path.parent, suffix=".tmp", delete=False) as handle:
        write(handle)
    os.replace(handle.name, path)
