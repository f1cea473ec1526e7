"""The project's cache on disk: where it is, and how a file gets into it.

``$HAWT_CACHE_DIR`` (default ``~/.cache/hawt``) holds what is computed from inputs and worth keeping between runs:
turbulent wind fields (:func:`hawt_plant.turbulence.cached_turbulence`), parsed turbine definitions
(:func:`hawt_plant.turbine.load_turbine`) and what a plant computes at its start from the turbine (:func:`kept`: the
operating point, the pitch actuator's discrete step), each in a folder of its own and named by a hash of what it was
computed from. The compiled kernels are not here (:mod:`hawt_plant.kernel_cache` says why).
"""
from __future__ import annotations

import hashlib
import os
import pickle
import tempfile
from functools import lru_cache
from pathlib import Path
from typing import IO, Any, Callable, TypeVar

from hawt_plant.kernel_cache import source_hash

__all__ = ["cache_root", "kept", "store"]

Result = TypeVar("Result")


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


@lru_cache(maxsize=None)
def _sources() -> bytes:
    return source_hash().encode()


def kept(name: str, inputs: Any, compute: Callable[[], Result]) -> Result:
    """``compute()``, kept on disk under ``name`` for ``inputs`` (anything picklable: a turbine, numbers) and
    hawt_plant's sources: a later call with equal inputs and sources loads the result instead.

    For what a plant computes at its start from its turbine with scipy (root finding, a matrix exponential): a
    result kept loads in well under a millisecond, where importing scipy.optimize and scipy.linalg takes 0.27 s of
    every process that starts a plant. The result loaded is the one computed, to the bit, so a run is the same with
    or without the cache. A cache that cannot be read or written costs the computation, nothing else.
    """
    digest = hashlib.sha256(_sources())
    digest.update(name.encode())
    digest.update(pickle.dumps(inputs, protocol=pickle.HIGHEST_PROTOCOL))
    path = cache_root() / "kept" / name / f"{digest.hexdigest()[:32]}.pickle"
    try:
        return pickle.loads(path.read_bytes())
    except (OSError, pickle.UnpicklingError, EOFError, AttributeError, TypeError):
        pass
    result = compute()
    try:
        store(path, lambda handle: pickle.dump(result, handle, protocol=pickle.HIGHEST_PROTOCOL))
    except OSError:
        pass
    return result
