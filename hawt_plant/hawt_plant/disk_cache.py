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
from pathlib import Path
from typing import IO, Any, Callable, TypeVar

from hawt_plant.kernel_cache import sources_key

__all__ = ["cache_root", "kept", "kept_at", "store"]

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


def kept_at(path: Path, compute: Callable[[], Result]) -> Result:
    """The result pickled at ``path``, or ``compute()``'s, pickled there for the next call.

    Either way the result is returned through its pickle, so a run gets the same object (and the same structure of
    shared references, which :func:`kept`'s keys pickle) whether it computed it or loaded it. A file that cannot be
    read or written costs the computation, nothing else (a file of other sources cannot be read: the callers' keys
    name the sources).
    """
    try:
        return pickle.loads(path.read_bytes())
    except (OSError, pickle.UnpicklingError, EOFError, AttributeError, TypeError):
        pass
    pickled = pickle.dumps(compute(), protocol=pickle.HIGHEST_PROTOCOL)
    try:
        store(path, lambda handle: handle.write(pickled))
    except OSError:
        pass
    return pickle.loads(pickled)


def kept(name: str, inputs: Any, compute: Callable[[], Result]) -> Result:
    """``compute()``, kept on disk under ``name`` for ``inputs`` (anything picklable: a turbine, numbers) and
    hawt_plant's sources (:func:`kept_at`): a later call with equal inputs and sources loads the result instead.

    For what a plant computes at its start from its turbine with scipy (root finding, a matrix exponential): a
    result kept loads in well under a millisecond, where importing scipy.optimize and scipy.linalg takes 0.27 s of
    every process that starts a plant. The result loaded is the one computed, to the bit, so a run is the same with
    or without the cache.
    """
    digest = hashlib.sha256(sources_key().encode())
    digest.update(name.encode())
    digest.update(pickle.dumps(inputs, protocol=pickle.HIGHEST_PROTOCOL))
    return kept_at(cache_root() / "kept" / name / f"{digest.hexdigest()[:32]}.pickle", compute)
