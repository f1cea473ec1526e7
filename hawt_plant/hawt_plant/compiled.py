"""Compiling the plant's per-element physics: numba, with a cache that can never be stale.

The per-step arithmetic of the plant (blade-element aerodynamics, dynamic stall, the induction) is written
once, in Python, as scalar functions and loops decorated with :func:`njit`; numba compiles them to machine
code on first use and keeps the result on disk. There is no second, interpreted copy of that physics.

numba's own cache checks only the time stamp of the file that holds a compiled function, not of the files
whose functions it calls, so a change to one module could leave another's compiled code calling the old
version. Here the cache folder is keyed instead by a hash of the content of every module of this package:
any change to the plant's sources selects a new, empty folder and everything is compiled again. A cache
folder is therefore never used for sources other than its own.

The folder is ``$NUMBA_CACHE_DIR`` when the user sets it (numba's own setting, then the user's to keep
in step), otherwise ``$XDG_CACHE_HOME/hawt/compiled/<hash>`` (``~/.cache`` by default). It is deliberately
not under ``$HAWT_CACHE_DIR`` (:mod:`hawt_plant.disk_cache`): what is kept there depends on inputs, this only on the
sources, and ``scripts/setup.sh`` fills it once (``python -m hawt_plant.compiled``). The folder and its key are
:mod:`hawt_plant.kernel_cache`'s, which set-up asks without importing numba.
"""
from __future__ import annotations

import os
import sys
from typing import Callable

import numpy as np

from hawt_plant.kernel_cache import cache_folder, source_hash

__all__ = ["cache_folder", "flat", "njit", "source_hash"]

os.environ["NUMBA_CACHE_DIR"] = str(cache_folder())  # read by numba when it is first imported (just below), and
# inherited by the processes this one starts

# Two imports numba makes for features the plant's kernels do not use, hidden from it while it loads (an ImportError
# to numba, which then goes without them), importable again afterwards for whoever wants them:
# - coverage (65 ms), only to report compiled lines to a coverage measurement running already;
# - scipy (numba.np.arraymath asks for scipy.linalg's BLAS as it loads, 0.15-0.25 s of a plant's start, to speed up
#   np.convolve and np.correlate; np.dot and np.linalg still find it when a kernel is typed with them).
_HIDDEN = [name for name in ("coverage", "scipy") if name not in sys.modules]
for _name in _HIDDEN:
    sys.modules[_name] = None  # type: ignore[assignment]
import numba  # noqa: E402  (after its cache folder is set)
import numba.np.arraymath  # noqa: E402,F401  (what the first kernel's load would import, here while scipy is hidden)
for _name in _HIDDEN:
    del sys.modules[_name]
from numba.core import caching as _caching  # noqa: E402
from numba.core import config as _numba_config  # noqa: E402

_numba_config.CACHE_DIR = os.environ["NUMBA_CACHE_DIR"]  # in case numba was imported before this module


class _RealPathLocator(_caching.UserProvidedCacheLocator):
    """numba's locator in the cache folder, keyed by the real path of a function's file rather than the path it was
    imported by: the workspace's build and install spaces link to the sources, and a plant imported through either
    (or from its source, as set-up compiles it) finds the same compiled kernels."""

    @classmethod
    def get_suitable_cache_subpath(cls, py_file: str) -> str:
        return super().get_suitable_cache_subpath(os.path.realpath(py_file))


if _RealPathLocator not in _caching.CacheImpl._locator_classes:
    _caching.CacheImpl._locator_classes.insert(0, _RealPathLocator)


def njit(function: Callable) -> Callable:
    """Compile ``function`` in nopython mode, cached on disk, with numpy's floating-point error model
    (a division by zero gives inf or NaN as in numpy, it does not raise) and without fast-math, so that
    results are IEEE arithmetic in the order written and runs stay deterministic."""
    return numba.njit(cache=True, error_model="numpy", fastmath=False)(function)


def flat(*arrays) -> tuple[tuple[int, ...], list]:
    """The common shape of ``arrays`` broadcast together, and each broadcast array as a flat, contiguous float
    array: what a compiled loop over the elements of an array interface takes."""
    arrays = [np.asarray(values, dtype=float) for values in arrays]
    if any(values.shape != arrays[0].shape for values in arrays):
        arrays = np.broadcast_arrays(*arrays)
    return arrays[0].shape, [np.ascontiguousarray(values).reshape(-1) for values in arrays]


def compile_all() -> None:
    """Compile (or load from the cache) every kernel of the plant, by building and stepping a model with every
    option that has a kernel of its own: what ``scripts/setup.sh`` runs, so that no run pays for compiling."""
    # a model imports this module, so these imports cannot be at its top
    from hawt_plant.model import ModelConfig, TurbineModel
    from hawt_plant.shear_wind import PowerLawWind
    from hawt_plant.turbine import nrel_5mw

    model = TurbineModel(nrel_5mw(), PowerLawWind(11.4, shear_exponent=0.2),
                         ModelConfig(unsteady_airfoil=True, skewed_wake=True))
    model.step(model.output.pitch, model.output.generator_torque)


if __name__ == "__main__":
    compile_all()
    print(f"hawt: compiled the plant's kernels ({cache_folder()})")
