"""Compiling the plant's per-element physics: numba, ahead of time where set-up could, with caches never stale.

The per-step arithmetic of the plant (blade-element aerodynamics, dynamic stall, the induction, the structure's step)
is written once, in Python, as scalar functions and loops decorated with :func:`njit`. There is no second,
interpreted copy of that physics. numba compiles it in one of two ways, from the same source:

- **Ahead of time** (the usual case). ``scripts/setup.sh`` runs :mod:`hawt_plant.kernel_export`, which compiles every
  kernel a run calls from Python into one extension module (numba's ``pycc``) with a manifest of the argument types
  each was compiled for. A process then loads that module (a millisecond) instead of importing numba and loading its
  cached kernels (about half a second of every plant's start on a 2-core VM).
- **Just in time**, numba's ``@njit(cache=True)``: when the extension is missing (a source edited since set-up), for
  a call whose arguments differ in type from what the extension was compiled for, and everywhere with
  ``HAWT_KERNELS=jit``.

numba's ahead-of-time functions do not check their arguments (a float32 array or a list is read as float64 memory),
so each call is checked against the manifest (:class:`Kernel`) and falls back to the just-in-time kernel when it does
not match. The plant's step passes only arrays it allocated itself, of the exact types, to the kernels it calls
through :func:`unchecked`, which skips the check; ``HAWT_KERNELS=checked`` checks those too (a test steps models in
every option set that way and finds no call that would have needed numba).

Both kinds of compiled code are kept in one folder keyed by a hash of the content of every module of this package
(numba's own cache checks only the time stamp of the file that holds a compiled function, not of the files whose
functions it calls): any change to the plant's sources selects a new, empty folder, so no compiled code is ever used
for sources other than its own. The folder is ``$NUMBA_CACHE_DIR`` when the user sets it (numba's own setting, then
the user's to keep in step), otherwise ``$XDG_CACHE_HOME/hawt/compiled/<hash>`` (``~/.cache`` by default). It is
deliberately not under ``$HAWT_CACHE_DIR`` (:mod:`hawt_plant.disk_cache`): what is kept there depends on inputs,
this only on the sources. The folder and its key are :mod:`hawt_plant.kernel_cache`'s, which set-up asks without
importing numba.
"""
from __future__ import annotations

import importlib.machinery
import importlib.util
import json
import os
import sys
import types
from functools import lru_cache
from typing import Any, Callable, Optional

import numpy as np

from hawt_plant.kernel_cache import cache_folder, source_hash

__all__ = ["EXTENSION", "Kernel", "cache_folder", "flat", "load_numba", "njit", "source_hash",
           "unchecked"]

EXTENSION = "hawt_plant_kernels"  # the ahead-of-time module's name, and its manifest's (``.json``) in the folder
_MODE = os.environ.get("HAWT_KERNELS", "")  # "jit": numba only; "checked": every ahead-of-time call checked
if _MODE not in ("", "jit", "checked"):
    print(f"HAWT_KERNELS={_MODE!r}: expected 'jit', 'checked' or unset", file=sys.stderr)
    sys.exit(2)

os.environ["NUMBA_CACHE_DIR"] = str(cache_folder())  # read by numba when it is first imported, and inherited by the
# processes this one starts


@lru_cache(maxsize=None)
def load_numba() -> types.ModuleType:
    """numba, imported on first need, with its cache in :func:`cache_folder`."""
    # Two imports numba makes for features the plant's kernels do not use, hidden from it while it loads (an
    # ImportError to numba, which then goes without them), importable again afterwards for whoever wants them:
    # - coverage (65 ms), only to report compiled lines to a coverage measurement running already;
    # - scipy (numba.np.arraymath asks for scipy.linalg's BLAS as it loads, 0.15-0.25 s of a plant's start, to speed
    #   up np.convolve and np.correlate; np.dot and np.linalg still find it when a kernel is typed with them).
    hidden = [name for name in ("coverage", "scipy") if name not in sys.modules]
    for name in hidden:
        sys.modules[name] = None  # type: ignore[assignment]
    try:
        import numba
        import numba.np.arraymath  # noqa: F401  (what the first kernel's load would import, here while scipy is hidden)
    finally:
        for name in hidden:
            del sys.modules[name]
    from numba.core import caching, config

    config.CACHE_DIR = os.environ["NUMBA_CACHE_DIR"]  # in case numba was imported before this module

    class RealPathLocator(caching.UserProvidedCacheLocator):
        """numba's locator in the cache folder, keyed by the real path of a function's file rather than the path it
        was imported by: the workspace's build and install spaces link to the sources, and a plant imported through
        either (or from its source, as set-up compiles it) finds the same compiled kernels."""

        @classmethod
        def get_suitable_cache_subpath(cls, py_file: str) -> str:
            return super().get_suitable_cache_subpath(os.path.realpath(py_file))

    caching.CacheImpl._locator_classes.insert(0, RealPathLocator)
    return numba


def _just_in_time(function: Callable) -> Callable:
    """numba's compiled dispatcher of ``function`` in nopython mode, cached on disk, with numpy's floating-point error
    model (a division by zero gives inf or NaN as in numpy, it does not raise) and without fast-math, so that results
    are IEEE arithmetic in the order written and runs stay deterministic."""
    return load_numba().njit(cache=True, error_model="numpy", fastmath=False)(function)


def _argument_check(spec: list) -> Callable[[Any], bool]:
    """Whether a Python value is one numba would type as this manifest entry: ``["float"]`` (float64), ``["int"]``
    (int64), ``["bool"]`` or ``["array", dtype, ndim, layout, writable]`` (layout "C", "F" or "A", any)."""
    kind = spec[0]
    if kind == "float":
        return lambda value: isinstance(value, float)  # a Python float or numpy's float64
    if kind == "int":
        return lambda value: isinstance(value, (int, np.int64)) and not isinstance(value, bool)
    if kind == "bool":
        return lambda value: isinstance(value, (bool, np.bool_))
    _, dtype, ndim, layout, writable = spec
    dtype, contiguous = np.dtype(dtype), {"C": "C_CONTIGUOUS", "F": "F_CONTIGUOUS"}.get(layout)

    def check(value: Any) -> bool:
        return (type(value) is np.ndarray and value.dtype == dtype and value.ndim == ndim
                and (contiguous is None or value.flags[contiguous]) and (not writable or value.flags.writeable))
    return check


class Kernel:
    """A kernel compiled ahead of time, called with its arguments checked against the types it was compiled for,
    and just in time (numba) for any other call. Called like the Python function it was made from."""

    def __init__(self, function: Callable, exports: list[tuple[Callable, list]]):
        self.py_func = function
        self.__name__, self.__qualname__, self.__doc__ = function.__name__, function.__qualname__, function.__doc__
        self.__module__, self.__wrapped__ = function.__module__, function
        self._exports = [(exported, len(specs), [_argument_check(spec) for spec in specs])
                         for exported, specs in exports]
        # The export for arrays allocated by their caller: every array C-contiguous (whether numba typed it writable
        # or read-only does not change how it is read); none where two such differ in another argument's type.
        contiguous = {json.dumps([spec[:4] for spec in specs]): exported for exported, specs in exports
                      if all(spec[0] != "array" or spec[3] == "C" for spec in specs)}
        self._contiguous = next(iter(contiguous.values())) if len(contiguous) == 1 else None
        self._dispatcher: Optional[Callable] = None

    def __call__(self, *args):
        for exported, count, checks in self._exports:
            if len(args) == count and all(check(value) for check, value in zip(checks, args)):
                return exported(*args)
        return self.dispatcher()(*args)

    def unchecked(self) -> Callable:
        """The ahead-of-time function itself, for a caller that passes only C-contiguous arrays (:func:`unchecked`);
        this kernel where it has no single such function or checking is asked for."""
        return self if _MODE == "checked" or self._contiguous is None else self._contiguous

    def dispatcher(self) -> Callable:
        """numba's just-in-time dispatcher of this kernel, compiled (or loaded from the cache) on first need, with the
        kernels it calls as numba dispatchers too."""
        if self._dispatcher is None:
            function = self.py_func
            kernels = {name: function.__globals__.get(name) for name in _global_names(function.__code__)}
            names = {name: value.dispatcher() for name, value in kernels.items() if isinstance(value, Kernel)}
            if names:
                copy = types.FunctionType(function.__code__, {**function.__globals__, **names}, function.__name__,
                                          function.__defaults__, function.__closure__)
                copy.__qualname__, copy.__module__, copy.__doc__ = (function.__qualname__, function.__module__,
                                                                    function.__doc__)
                function = copy
            self._dispatcher = _just_in_time(function)
        return self._dispatcher


def _global_names(code: types.CodeType) -> set[str]:
    """The global names ``code`` and the functions defined in it read."""
    nested = (_global_names(constant) for constant in code.co_consts if isinstance(constant, types.CodeType))
    return set(code.co_names).union(*nested)


@lru_cache(maxsize=None)
def _ahead_of_time() -> tuple[Optional[types.ModuleType], dict]:
    """The extension :mod:`hawt_plant.kernel_export` compiled for these sources, and its manifest (export name to its
    function and argument types); ``(None, {})`` where there is none (or ``HAWT_KERNELS=jit``)."""
    if _MODE == "jit":
        return None, {}
    folder = cache_folder()
    manifest = folder / f"{EXTENSION}.json"  # written after the extension: its presence says the build completed
    if not manifest.is_file():
        return None, {}
    path = folder / f"{EXTENSION}{importlib.machinery.EXTENSION_SUFFIXES[0]}"
    spec = importlib.util.spec_from_file_location(EXTENSION, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module, json.loads(manifest.read_text())


def njit(function: Callable) -> Callable:
    """Compile ``function``: its ahead-of-time form as a :class:`Kernel` where set-up built one for these sources,
    else numba's just-in-time dispatcher (see the module notes)."""
    module, manifest = _ahead_of_time()
    if module is None:
        return _just_in_time(function)
    name = f"{function.__module__}.{function.__qualname__}"
    return Kernel(function, [(getattr(module, export), entry["arguments"])
                             for export, entry in manifest.items() if entry["function"] == name])


def unchecked(kernel: Callable) -> Callable:
    """What the plant's step calls for ``kernel`` (an :func:`njit` function): the ahead-of-time function without the
    check of its arguments' types, for a caller that passes only arrays it allocated as float64 and C-contiguous and
    plain floats and ints (:class:`Kernel`); the kernel itself where it has no single ahead-of-time form."""
    return kernel.unchecked() if isinstance(kernel, Kernel) else kernel


def flat(*arrays) -> tuple[tuple[int, ...], list]:
    """The common shape of ``arrays`` broadcast together, and each broadcast array as a flat, contiguous float
    array: what a compiled loop over the elements of an array interface takes."""
    arrays = [np.asarray(values, dtype=float) for values in arrays]
    if any(values.shape != arrays[0].shape for values in arrays):
        arrays = np.broadcast_arrays(*arrays)
    return arrays[0].shape, [np.ascontiguousarray(values).reshape(-1) for values in arrays]
