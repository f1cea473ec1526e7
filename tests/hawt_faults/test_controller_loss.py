"""The cpc lost mid-run: the plant's safety system trips, feathers at the rate limit, latches, and the run completes."""

import numpy as np
import pytest
from hawt_msgs.msg import ControlEvent, PitchCommand

from hawt_plant.turbine import nrel_5mw

from hawt_faults.fault_runs import (ACTUATOR, DT, assert_pitch_within_limits, assert_plant_finished,
                                    assert_plant_published_no_nan, feather_ramp, graph_outliving, read_recording,
                                    rises_at_rate_limit)

pytestmark = pytest.mark.ros

FEATHER_DURATION = 40.0
"""Simulated run [s]: the cpc dies after about 3 s, the watchdog trips 3 s later (command_timeout) and feathering
from 15 deg at 8 deg/s takes 9.4 s. The cpc dies only once the test has seen the recorder subscribe and the loop
answer, which a busy machine delays: in one fresh-clone run an 18 s realtime run ended before the watchdog could trip,
and in a busy suite an 18 s lockstep run did (the plant ran on while the test process waited for a core); a 40 s one
did too, the probe not yet matched: the plant now starts only once the probe is, its fourth subscriber on
plant/blade_loads beside the recorder, cpc and mbc."""


@pytest.mark.parametrize("mode", ["lockstep", "realtime"])
def test_a_killed_cpc_trips_the_plant_to_feather_at_the_rate_limit_latched_and_the_run_completes(mode, launch, probe,
                                                                                                  tmp_path):
    """cpc SIGKILLed: a watchdog ERROR; pitch rises at <= 8 deg/s to 90 deg despite returning commands; run ends."""
    namespace = f"cpc_lost_{mode}"
    watcher = probe(namespace)
    run = launch(str(graph_outliving(tmp_path, "baseline", "cpc")), namespace, f"mode:={mode}",
                 f"duration:={FEATHER_DURATION:g}", "-p", "plant.command_sources:=['mbc', '/fault_probe']",
                 "-p", "plant.wait_for_subscribers:=4")
    watcher.wait_until_recorded(run.launcher)
    run.kill("cpc")
    watcher.wait_for_event("watchdog", run.launcher)
    watcher.publish_until({"control/pitch_command": lambda step: PitchCommand(step=step, pitch=[0.0] * 3,
                                                                              generator_torque=4e4)},
                          lambda: watcher.reported("command_returned"), run.launcher, "command_returned")
    run.finish()

    recording = read_recording(run.bag, namespace)
    (watchdog,) = recording.events_of("watchdog")
    assert watchdog["level"] == ControlEvent.ERROR
    assert watchdog["source"] == f"/{namespace}/plant"
    assert "control/pitch_command" in watchdog["detail"] and "command_timeout 3 s" in watchdog["detail"]
    (died,) = recording.events_of("node_respawn")  # the launcher reports the death (its respawn waits 3600 s)
    assert died["source"] == "/hawt_launch" and died["level"] == ControlEvent.WARN
    assert f"/{namespace}/cpc ended (killed by SIGKILL)" in died["detail"] and 0 < died["step"] <= watchdog["step"]
    (returned,) = recording.events_of("command_returned")
    assert returned["level"] == ControlEvent.WARN and returned["step"] >= watchdog["step"]
    assert "the trip is latched" in returned["detail"]
    ramp = feather_ramp(recording, watchdog["step"])
    assert rises_at_rate_limit(ramp) is None, rises_at_rate_limit(ramp)
    # The cpc is killed when the test sees enough answers; on a busy machine a lockstep plant may be far into the
    # run by then. Every blade reaches feather, or, if the run ends first, as far as the rate limit allows
    # (less the second-order actuator's lag, rate x 2 zeta / omega_n at the end of a long ramp; on the way the
    # underdamped actuator lags up to 16 % more (zeta 0.6), and the trip acts from the next step).
    lag = 1.2 * 2 * ACTUATOR.damping_ratio / ACTUATOR.natural_frequency
    reachable = min(ACTUATOR.max_angle, ramp[0].min() + ACTUATOR.max_rate * (DT * (len(ramp) - 1) - lag))
    assert np.all(ramp[-1] > reachable - ACTUATOR.max_rate * DT), f"the blades stopped at {np.degrees(ramp[-1])} deg"
    # The generator torque goes to 0 at its rate limit: reached, or as far as the run's remaining time allows.
    steps, torque = (np.asarray(recording.state.fields[name]) for name in ("step", "generator_torque"))
    at_trip = torque[steps <= watchdog["step"]][-1]
    remaining = DT * (steps[-1] - watchdog["step"])
    assert torque[-1] <= max(0.0, at_trip - nrel_5mw().generator.max_torque_rate * (remaining - DT)), \
        f"the torque {torque[-1]:.0f} N*m did not fall from {at_trip:.0f} N*m at the rate limit in {remaining:.2f} s"
    assert_plant_finished(recording, FEATHER_DURATION)
    assert_plant_published_no_nan(recording)
    assert_pitch_within_limits(recording)
