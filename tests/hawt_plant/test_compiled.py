"""Specification of hawt_plant.compiled: the plant's kernels are compiled, and never from other sources."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import hawt_plant
from hawt_plant import (airfoil_table, bem, blade_elements, grid_sampling, model_step, pitch_actuator, shear_wind,
                        tower_drag, tower_shadow, unsteady_airfoil)
from hawt_plant.compiled import Kernel, cache_folder, source_hash
from hawt_plant.model import ModelConfig, TurbineModel
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbine import nrel_5mw

PACKAGE = Path(hawt_plant.__file__).resolve().parent


def test_the_per_step_formulas_are_compiled_ahead_of_time_by_set_up():
    """Each formula of a step is compiled: set-up built the extension for these sources, so each is a kernel with its
    ahead-of-time functions (a numba dispatcher only with HAWT_KERNELS=jit, or before set-up compiled them)."""
    for function in (blade_elements.blade_element_loads, bem.induction, bem.loss_factor, bem.skew_factor,
                     bem.inflow_angle, airfoil_table.grid_point, unsteady_airfoil.hgm_step, grid_sampling.trilinear,
                     model_step.place_elements, model_step.element_inflow, model_step.generalized_forces,
                     model_step.accelerations, model_step.advance_structure, model_step.measured_loads,
                     model_step.advance, model_step.skew_geometry, model_step.acting_torque,
                     model_step.loads_and_measurements, shear_wind.power_law,
                     tower_shadow.shadow, tower_drag.node_drag, pitch_actuator.limited_step):
        assert isinstance(function, Kernel) and function.unchecked() is not function, function


def _in_a_process(code: str, **environment: str) -> str:
    """What ``code`` prints in a new Python process with ``environment`` added."""
    return subprocess.run([sys.executable, "-c", code], env={**os.environ, **environment}, capture_output=True,
                          text=True, check=True).stdout


STEPPED = """
import sys, numpy as np
from hawt_plant.model import ModelConfig, TurbineModel
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbine import nrel_5mw
model = TurbineModel(nrel_5mw(), PowerLawWind(14.0, shear_exponent=0.2),
                     ModelConfig(unsteady_airfoil=True, skewed_wake=True, dynamic_inflow=True))
out, rows = model.output, []
for k in range(300):
    out = model.step(out.pitch + 0.01 * np.sin(0.05 * k), out.generator_torque)
    rows.append(np.concatenate((out.root_moment_oop, out.root_moment_ip, [out.rotor_speed, out.tower_base_fa_moment])))
print("numba" in sys.modules, np.array(rows).tobytes().hex())
"""


def test_a_run_ahead_of_time_imports_no_numba_and_equals_the_just_in_time_run_to_the_bit():
    """The ahead-of-time kernels are the just-in-time ones compiled for the same CPU with the same error model: 300
    steps with every aerodynamic option agree bit for bit, and the process never imported numba."""
    ahead, ahead_rows = _in_a_process(STEPPED).split()
    jit, jit_rows = _in_a_process(STEPPED, HAWT_KERNELS="jit").split()
    assert (ahead, jit) == ("False", "True")
    assert ahead_rows == jit_rows


CHECKED = """
import sys, numpy as np
from hawt_plant.model import ModelConfig, TurbineModel
from hawt_plant.shear_wind import PowerLawWind
from hawt_plant.turbine import load_turbine, nrel_5mw, nrel_5mw_two_bladed_downwind
from hawt_plant.turbulence import TurbulentWind
for turbine in (nrel_5mw(), nrel_5mw_two_bladed_downwind(), *map(load_turbine, sys.argv[1:])):
    grid, hub = np.linspace(-130.0, 130.0, 7), turbine.tower.height
    field = TurbulentWind(11.0 + np.random.default_rng(1).normal(size=(8, 7, 7, 3)), time_step=0.5, grid_y=grid,
                          grid_z=hub + 5.0 + grid, mean_speed=11.0, hub_height=hub)
    for wind, config in ((PowerLawWind(11.4, shear_exponent=0.2),
                          ModelConfig(unsteady_airfoil=True, skewed_wake=True, dynamic_inflow=True)),
                         (field, ModelConfig(tower_drag=False)), (PowerLawWind(30.0), ModelConfig(rotor="parked")),
                         (PowerLawWind(30.0), ModelConfig(rotor="idling"))):
        model = TurbineModel(turbine, wind, config)
        for _ in range(3):
            model.step(model.output.pitch, model.output.generator_torque)
print("numba" in sys.modules)
"""


def test_the_step_passes_its_unchecked_kernels_exactly_the_types_they_were_compiled_for(rosco_case, tmp_path):
    """The step calls its kernels without checking their arguments' types (a wrong one would be read as float64
    memory): checked here, on three turbines (one imported from an OpenFAST deck) in every option set, every call
    matches an ahead-of-time function, so none needed numba."""
    deck = rosco_case("IEA-15-240-RWT/IEA-15-240-RWT-Monopile/IEA-15-240-RWT-Monopile.fst")
    subprocess.run([sys.executable, "-m", "hawt_tools.cli", "turbine", "import", str(deck), "-o", str(tmp_path / "iea")],
                   check=True, capture_output=True)
    code = CHECKED.replace("sys.argv[1:]", repr([str(tmp_path / "iea" / "turbine.yaml")]))
    assert _in_a_process(code, HAWT_KERNELS="checked").split() == ["False"]


def test_a_call_with_other_types_is_compiled_just_in_time_never_misread():
    """Ahead-of-time functions read any argument as the type they were compiled for; a kernel checks, and calls
    numba's just-in-time kernel for arguments of other types (a float32 array, a strided view, integers)."""
    code = """
import sys, numpy as np
from hawt_plant.model_step import advance_structure
def advanced(acc, dt, velocity, displacement):
    advance_structure(acc, dt, velocity, displacement)
    return np.concatenate((velocity, displacement))
exact = advanced(np.array([1.0, 2.0, 3.0, 9.0]), 0.5, np.array([1.0, -1.0, 0.5]), np.zeros(3))
assert 'numba' not in sys.modules
for acc in (np.array([1, 2, 3, 9], dtype=np.float32), np.array([1.0, 0.0, 2.0, 0.0, 3.0, 0.0, 9.0])[::2],
            np.array([1, 2, 3, 9])):
    assert advanced(acc, 0.5, np.array([1.0, -1.0, 0.5]), np.zeros(3)).tolist() == exact.tolist(), acc
print('numba' in sys.modules)
"""
    assert _in_a_process(code).split() == ["True"]


def test_the_step_kernels_take_every_constant_by_name_and_no_other():
    """The model's scalar constants reach the kernels as one array in the order of CONSTANTS; a missing or unknown
    name is refused, naming it."""
    values = {name: float(k) for k, name in enumerate(model_step.CONSTANTS)}
    assert model_step.constant_array(**values).tolist() == list(values.values())
    del values["hub_mass"]
    with pytest.raises(ValueError, match="missing \\['hub_mass'\\], unknown \\['hub_masss'\\]"):
        model_step.constant_array(**values, hub_masss=1.0)


def test_the_cache_is_keyed_by_the_content_of_every_plant_module(tmp_path):
    """A changed byte in any module selects another cache folder; a touched file (time stamp only) does not."""
    copy = tmp_path / "hawt_plant"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    assert source_hash(copy) == source_hash(PACKAGE)
    os.utime(copy / "bem.py", (0, 0))
    assert source_hash(copy) == source_hash(PACKAGE)
    module = copy / "tower_drag.py"  # a module no kernel lives in: its change still counts
    module.write_text(module.read_text() + "\n")
    assert source_hash(copy) != source_hash(PACKAGE)
    assert cache_folder().name == source_hash()


def test_numba_cache_dir_set_by_the_user_is_where_the_kernels_go(tmp_path):
    """NUMBA_CACHE_DIR, numba's own setting, overrides the keyed folder, and the kernels are written there."""
    code = ("from hawt_plant.compiled import cache_folder; from hawt_plant.bem import loss_factor; "
            "loss_factor(0.5, 1.0, 1.0); print(cache_folder())")
    result = subprocess.run([sys.executable, "-c", code], env={**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)},
                            capture_output=True, text=True, check=True)
    assert result.stdout.strip() == str(tmp_path)
    assert any(tmp_path.rglob("*.nbi"))  # numba's index of a cached function


def test_a_compiled_step_is_deterministic():
    """Two models stepped alike agree bit for bit (no fast-math, no threads)."""
    def run() -> np.ndarray:
        model = TurbineModel(nrel_5mw(), PowerLawWind(14.0, shear_exponent=0.2),
                             ModelConfig(unsteady_airfoil=True, skewed_wake=True, bem_iterations=2))
        out = model.output
        rows = []
        for k in range(200):
            out = model.step(out.pitch + 0.01 * np.sin(0.05 * k), out.generator_torque)
            rows.append(np.concatenate((out.root_moment_oop, [out.rotor_speed, out.tower_base_fa_moment])))
        return np.array(rows)

    np.testing.assert_array_equal(run(), run())


def test_a_plant_imported_through_a_link_finds_the_kernels_compiled_from_its_source(tmp_path):
    """The workspace's build and install spaces link to the sources: importing the plant through a link uses the
    kernels set-up compiled from the source (one folder of compiled code, not one per import path)."""
    link = tmp_path / "linked"
    link.mkdir()
    (link / "hawt_plant").symlink_to(PACKAGE)
    cache = tmp_path / "cache"
    code = "from hawt_plant.bem import loss_factor; loss_factor(0.5, 1.0, 1.0)"
    for root in (PACKAGE.parent, link):
        path = os.pathsep.join([str(root), os.environ.get("PYTHONPATH", "")])
        subprocess.run([sys.executable, "-c", code], env={**os.environ, "NUMBA_CACHE_DIR": str(cache),
                                                          "PYTHONPATH": path}, check=True, cwd=tmp_path)
    assert len([folder for folder in cache.iterdir() if folder.is_dir()]) == 1
