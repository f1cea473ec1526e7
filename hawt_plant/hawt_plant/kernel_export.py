"""Compiling the plant's kernels once, at set-up: just in time into numba's cache, then ahead of time into an extension.

``python -m hawt_plant.kernel_export`` (``scripts/setup.sh`` runs it once per change of the plant's sources):

1. steps models in the option sets that have kernels or argument types of their own (:func:`exercise`), with every
   kernel compiled just in time, so that numba's cache holds them and each kernel the plant calls from Python has the
   signatures a run calls it with;
2. compiles those signatures into one extension module with numba's ``pycc`` (:data:`hawt_plant.compiled.EXTENSION`
   in :func:`~hawt_plant.compiled.cache_folder`), for the host's CPU as the just-in-time kernels are, with numpy's
   floating-point error model, and writes its manifest (each export's function and argument types) last, which marks
   the build complete. :mod:`hawt_plant.compiled` says how a run uses them.

numba's ``pycc`` is pending deprecation (numba 0.68, pinned); when it goes, the just-in-time kernels remain, and the
start of a plant process is half a second longer.
"""
from __future__ import annotations

import json
import os
import sys
from pathlib import Path
from typing import Optional

os.environ["HAWT_KERNELS"] = "jit"  # noqa: E402  (this process compiles every kernel just in time, to collect them)

import numpy as np  # noqa: E402

from hawt_plant.compiled import EXTENSION, cache_folder, load_numba  # noqa: E402
from hawt_plant.disk_cache import store  # noqa: E402

__all__ = ["exercise", "export"]


def exercise() -> None:
    """Build and step models with every option that has a kernel or argument types of its own: the deck's options
    (unsteady airfoil, skewed wake) in sheared wind, then a turbulent field, dynamic inflow and a parked rotor."""
    from hawt_plant.model import ModelConfig, TurbineModel
    from hawt_plant.shear_wind import PowerLawWind
    from hawt_plant.turbine import nrel_5mw
    from hawt_plant.turbulence import TurbulentWind

    turbine = nrel_5mw()
    grid = np.linspace(-70.0, 70.0, 5)
    field = TurbulentWind(11.4 + np.random.default_rng(1).normal(size=(8, 5, 5, 3)), time_step=0.5, grid_y=grid,
                          grid_z=turbine.tower.height + grid, mean_speed=11.4, hub_height=turbine.tower.height)
    for wind, config in ((PowerLawWind(11.4, shear_exponent=0.2), ModelConfig(unsteady_airfoil=True, skewed_wake=True)),
                         (field, ModelConfig()), (PowerLawWind(8.0), ModelConfig(dynamic_inflow=True)),
                         (PowerLawWind(30.0), ModelConfig(rotor="parked"))):
        model = TurbineModel(turbine, wind, config)
        for _ in range(2):
            model.step(model.output.pitch, model.output.generator_torque)


def _argument(numba_type) -> Optional[list]:
    """The manifest's entry for an argument of this numba type (:func:`hawt_plant.compiled._argument_check`); None
    for a type a Python value cannot be checked against cheaply (a literal, a tuple): such a signature stays just in
    time."""
    types = load_numba().types
    if isinstance(numba_type, types.Array):
        return ["array", str(numba_type.dtype), numba_type.ndim, numba_type.layout, numba_type.mutable]
    for kind, numba_kind in (("float", types.float64), ("int", types.int64), ("bool", types.boolean)):
        if numba_type == numba_kind:
            return [kind]
    return None


def export(folder: Path) -> int:
    """Compile every kernel's signatures seen so far into the extension in ``folder`` and write its manifest; the
    number of functions exported (one per signature)."""
    numba = load_numba()
    from llvmlite import binding
    from numba.core.compiler import Flags
    from numba.pycc import CC, compiler

    class NumpyErrors(Flags):
        """pycc's flags for an exported function with the just-in-time kernels' error model (a division by zero
        gives inf or NaN, as in numpy); the functions it calls keep their own."""

        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            self.error_model = "numpy"

    extension = CC(EXTENSION)
    extension.output_dir = str(folder)
    extension.target_cpu = binding.get_host_cpu_name()  # as numba compiles just in time
    manifest = {}
    for module_name, module in sorted(sys.modules.items()):
        if not module_name.startswith("hawt_plant.") or module is None:
            continue
        for name, kernel in vars(module).items():
            if not isinstance(kernel, numba.core.registry.CPUDispatcher) or kernel.__module__ != module_name:
                continue
            for k, signature in enumerate(kernel.nopython_signatures):
                arguments = [_argument(argument) for argument in signature.args]
                if None in arguments:
                    continue
                export_name = f"{module_name.split('.')[-1]}__{name}__{k}"
                extension.export(export_name, signature)(kernel.py_func)
                manifest[export_name] = {"function": f"{module_name}.{kernel.__qualname__}", "arguments": arguments}
    pycc_flags = compiler.Flags
    compiler.Flags = NumpyErrors
    try:
        extension.compile()
    finally:
        compiler.Flags = pycc_flags
    store(folder / f"{EXTENSION}.json", lambda handle: handle.write(json.dumps(manifest, indent=1).encode()))
    return len(manifest)


if __name__ == "__main__":
    exercise()
    folder = cache_folder()
    count = export(folder)
    print(f"hawt: compiled the plant's kernels just in time, and {count} functions of them ahead of time ({folder})")
