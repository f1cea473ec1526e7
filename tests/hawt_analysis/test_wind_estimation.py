"""A wind estimate against the plant's truth (issue 16): the figures on signals with a known answer, and lqg_ipc's
estimate in a turbulent run as `hawt analyze` reports it."""
import subprocess

import numpy as np
import pytest
from scipy.signal import butter, sosfiltfilt

from hawt_analysis.analysis_report import analysis_text, write_analysis_report
from hawt_analysis.run_analysis import analyze_bag
from hawt_analysis.wind_estimation import estimate_quality

RATE = 100.0


@pytest.fixture(scope="module")
def wind():
    rng = np.random.default_rng(4)
    return sosfiltfilt(butter(2, 1.0, fs=RATE, output="sos"), rng.standard_normal(60000))


def test_an_estimate_off_by_a_constant_is_perfect_and_the_constant_is_its_offset(wind):
    quality = estimate_quality(wind, wind + 1.5, RATE)
    assert quality.correlation == pytest.approx(1.0)
    assert quality.error_rms == pytest.approx(0.0, abs=1e-12)
    assert quality.offset == pytest.approx(1.5)
    assert np.all(quality.error_psd < 1e-20)


def test_an_estimate_that_follows_only_the_slow_wind_has_its_error_above_its_bandwidth(wind):
    """An estimate that is the wind low-passed at 0.1 Hz: the error's spectrum is the truth's above 0.1 Hz and far
    below it at low frequency; the correlation is Pearson's."""
    slow = sosfiltfilt(butter(4, 0.1, fs=RATE, output="sos"), wind)
    quality = estimate_quality(wind, slow, RATE)
    assert quality.correlation == pytest.approx(np.corrcoef(wind, slow)[0, 1], rel=1e-9)
    low, high = quality.frequencies < 0.03, (quality.frequencies > 0.5) & (quality.frequencies < 2.0)
    assert np.all(quality.error_psd[low][1:] < 0.05 * quality.truth_psd[low][1:])
    assert np.allclose(quality.error_psd[high], quality.truth_psd[high], rtol=0.05)


def test_series_of_different_lengths_are_refused():
    with pytest.raises(ValueError, match="estimate and truth"):
        estimate_quality(np.zeros(10), np.zeros(9), RATE)


@pytest.mark.ros
def test_hawt_analyze_reports_lqg_ipc_s_estimate_against_the_truth_of_a_turbulent_run(hawt_cli, tmp_path):
    """120 s of the lqg graph in turbulence at 18 m/s: the estimate follows the slow wind (correlation about 0.67
    over the whole band in a 300 s run), the report has its figure."""
    bag = tmp_path / "lqg.mcap"
    result = subprocess.run([*hawt_cli, "run", "lqg", "wind_type:=turbulent", "duration:=120", "seed:=1", "--record",
                             str(bag)], capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr[-2000:]
    analysis = analyze_bag(bag)
    estimate = analysis.summary["wind_estimate"]["lqg_ipc"]
    for axis in ("cos", "sin"):
        assert 0.5 < estimate[axis]["correlation"] < 1.0
        assert estimate[axis]["error_rms"] < estimate[axis]["truth_rms"]
    assert "wind estimate of lqg_ipc" in analysis_text(analysis.summary)
    write_analysis_report(analysis, tmp_path / "report")
    assert (tmp_path / "report" / "wind_estimate_lqg_ipc.png").stat().st_size > 10000
