"""Where the plant's compiled kernels are kept: a folder keyed by the content of the plant's sources.

:mod:`hawt_plant.compiled` says why (its module notes); this module holds only the key and the folder, without
importing numba, so that ``scripts/setup.sh`` can ask whether the kernels of these sources are compiled in a few
milliseconds instead of numba's import (a tenth of a second and more, paid by every ``./hawt`` command).
"""
from __future__ import annotations

import hashlib
import os
from functools import lru_cache
from pathlib import Path

__all__ = ["cache_folder", "source_hash", "sources_key"]

_PACKAGE = Path(__file__).resolve().parent
# the user's (or a parent process's) folder, read before hawt_plant.compiled sets it
_CHOSEN = os.environ.get("NUMBA_CACHE_DIR")


def source_hash(package: Path = _PACKAGE) -> str:
    """A short hash of the content of every module of ``package`` (``hawt_plant``): the key of the compiled
    cache."""
    digest = hashlib.sha256()
    for path in sorted(package.glob("*.py")):
        digest.update(path.name.encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


@lru_cache(maxsize=None)
def sources_key() -> str:
    """:func:`source_hash` of this package, read once per process (about 0.7 ms each time): the key of everything
    kept for these sources (the compiled kernels, and :mod:`hawt_plant.disk_cache`'s parsed turbines and results)."""
    return source_hash()


def cache_folder() -> Path:
    """Where numba keeps the compiled functions of these sources (see the module notes)."""
    if _CHOSEN:
        return Path(_CHOSEN)
    root = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return root / "hawt" / "compiled" / sources_key()


if __name__ == "__main__":
    print(cache_folder())
