"""Specification of hawt_plant.disk_cache.kept: what a plant computes at its start, kept on disk by its inputs."""
import os
import pickle
import subprocess
import sys

import numpy as np

from hawt_plant.disk_cache import kept
from hawt_plant.operating_point import baseline_operating_point
from hawt_plant.turbine import nrel_5mw


def test_a_kept_result_is_the_computed_one_to_the_bit_and_is_computed_once_per_input(tmp_path, monkeypatch):
    """The second call with equal inputs loads what the first computed; other inputs compute again."""
    monkeypatch.setenv("HAWT_CACHE_DIR", str(tmp_path))
    calls = []

    def compute(scale):
        calls.append(scale)
        return np.sin(np.arange(5.0) * scale) / 3.0

    first = kept("sines", (0.1,), lambda: compute(0.1))
    again = kept("sines", (0.1,), lambda: compute(0.1))
    other = kept("sines", (0.2,), lambda: compute(0.2))
    assert calls == [0.1, 0.2]
    assert first.tobytes() == again.tobytes() == compute(0.1).tobytes() and other.tobytes() != first.tobytes()
    assert len(list((tmp_path / "kept" / "sines").glob("*.pickle"))) == 2


def test_an_unreadable_or_unwritable_cache_costs_the_computation_only(tmp_path, monkeypatch):
    """A damaged file is computed again (and replaced); a cache folder that cannot be written is skipped."""
    monkeypatch.setenv("HAWT_CACHE_DIR", str(tmp_path))
    kept("value", (1,), lambda: 41)
    (stored,) = (tmp_path / "kept" / "value").glob("*.pickle")
    stored.write_bytes(b"\x80\x05 not a pickle")
    assert kept("value", (1,), lambda: 42) == 42 and pickle.loads(stored.read_bytes()) == 42
    blocked = tmp_path / "file"
    blocked.write_text("a file where the cache folder would be")
    monkeypatch.setenv("HAWT_CACHE_DIR", str(blocked))
    assert kept("value", (1,), lambda: 43) == 43


def test_the_operating_point_kept_is_the_solved_one(tmp_path, monkeypatch):
    """Above rated (Brent's method on the pitch) the kept operating point equals a fresh solution in every field."""
    monkeypatch.setenv("HAWT_CACHE_DIR", str(tmp_path))
    solved = baseline_operating_point(nrel_5mw(), 18.0)
    loaded = baseline_operating_point(nrel_5mw(), 18.0)
    assert pickle.dumps(loaded) == pickle.dumps(solved) and 0.2 < solved.pitch < 0.3


def test_a_plant_started_again_in_the_same_wind_imports_no_scipy(tmp_path):
    """The second start of the same plant finds its operating point kept (the first solves it with scipy.optimize),
    and numba loads the kernels without scipy (hawt_plant.compiled hides it from numba's array math, which asks for
    scipy.linalg's BLAS only for np.convolve and np.correlate, used by no kernel): no scipy is imported at all. And
    scipy imports as usual afterwards."""
    script = ("import sys\nfrom hawt_plant.plant_setup import PARAMETERS, make_plant\n"
              "make_plant({spec.name: spec.default for spec in PARAMETERS})\n"
              "loaded = 'scipy' in sys.modules\nimport scipy.linalg\nprint(loaded, scipy.linalg.norm([3.0, 4.0]))\n")
    environment = dict(os.environ, HAWT_CACHE_DIR=str(tmp_path))
    runs = [subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=environment,
                           timeout=300) for _ in range(2)]
    assert [run.stdout.split()[-2:] for run in runs] == [["True", "5.0"], ["False", "5.0"]], \
        [run.stderr[-2000:] for run in runs]
