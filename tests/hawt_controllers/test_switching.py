"""Switch semantics (ros2_control's STRICT / BEST_EFFORT, one controller per harmonic) and who publishes when."""
import math

import pytest

from hawt_controllers.switching import (ControllerInfo, HarmonicWindows, Switch, SwitchRefused, parse_schedule,
                                        plan_switch, ramp_steps)


def _controllers(**states):
    infos = {"/wt1/cpc": ControllerInfo("/wt1/cpc", "cpc", 0, "active", switchable=False)}
    for name, state in states.items():
        harmonic = int(name[5])
        infos[f"/wt1/{name}"] = ControllerInfo(f"/wt1/{name}", "ipc", harmonic, state,
                                               publishing_until=math.inf if state == "active" else 0.0)
    return infos


def test_strict_refuses_the_whole_switch_when_one_name_is_unknown():
    """STRICT: an unknown name refuses everything, naming it and the known controllers."""
    with pytest.raises(SwitchRefused, match="ipc_h9: no such controller"):
        plan_switch(_controllers(ipc_h1="inactive"), ["ipc_h1", "ipc_h9"], [], strict=True, step=10)


def test_best_effort_applies_what_it_can_and_says_what_it_skipped():
    """BEST_EFFORT: the known controller is activated, the unknown one is reported as skipped."""
    incoming, outgoing, skipped = plan_switch(_controllers(ipc_h1="inactive"), ["ipc_h1", "ipc_h9"], [],
                                              strict=False, step=10)
    assert [c.name for c in incoming] == ["/wt1/ipc_h1"] and outgoing == [] and "ipc_h9" in skipped[0]


def test_best_effort_with_nothing_left_is_refused():
    """BEST_EFFORT still refuses a switch in which nothing can be done."""
    with pytest.raises(SwitchRefused, match="nothing to switch"):
        plan_switch(_controllers(ipc_h1="active"), ["ipc_h1"], [], strict=False, step=10)


def test_a_second_active_controller_of_a_harmonic_is_refused_but_a_swap_is_allowed():
    """Activating ipc_h1b while ipc_h1a is active is refused; activating it while deactivating ipc_h1a is a swap."""
    controllers = _controllers(ipc_h1a="active", ipc_h1b="inactive")
    with pytest.raises(SwitchRefused, match="active controller of harmonic 1"):
        plan_switch(controllers, ["ipc_h1b"], [], strict=True, step=10)
    incoming, outgoing, _ = plan_switch(controllers, ["ipc_h1b"], ["ipc_h1a"], strict=True, step=10)
    assert Switch(10, tuple((c.name, c.harmonic) for c in incoming),
                  tuple((c.name, c.harmonic) for c in outgoing)).replaced(1)


def test_a_controller_cannot_come_in_while_another_still_ramps_out_its_harmonic():
    """The outgoing contribution must reach zero before another controller of that harmonic publishes."""
    controllers = _controllers(ipc_h1b="inactive")
    controllers["/wt1/ipc_h1a"] = ControllerInfo("/wt1/ipc_h1a", "ipc", 1, "inactive", publishing_until=250)
    with pytest.raises(SwitchRefused, match="still ramps out harmonic 1 until step 250"):
        plan_switch(controllers, ["ipc_h1b"], [], strict=True, step=200)
    assert plan_switch(controllers, ["ipc_h1b"], [], strict=True, step=250)[0]


def test_the_collective_controller_cannot_be_switched_off():
    """Deactivating cpc is refused with the reason (the safety system would stop the turbine)."""
    with pytest.raises(SwitchRefused, match="cpc controller cannot be switched"):
        plan_switch(_controllers(), [], ["cpc"], strict=True, step=10)


def test_ramp_steps_is_the_number_of_steps_the_output_takes_to_reach_zero():
    """ceil(ramp_time / dt): 1 s at 100 Hz is 100 steps, 0.015 s is 2, 0 is 0."""
    assert (ramp_steps(1.0, 0.01), ramp_steps(0.015, 0.01), ramp_steps(0.0, 0.01)) == (100, 2, 0)
    with pytest.raises(SwitchRefused, match="ramp_time"):
        ramp_steps(math.nan, 0.01)


def test_windows_follow_activation_ramp_out_and_swap():
    """h1 publishes from its activation; h2 until its ramp ends; a swap of h1 leaves no gap."""
    windows = HarmonicWindows([2], dt=0.01)
    windows.apply(Switch(100, activate=(("/a", 1),), ramp_time=1.0))
    windows.apply(Switch(200, deactivate=(("/b", 2),), ramp_time=0.5))
    windows.apply(Switch(300, activate=(("/c", 1),), deactivate=(("/a", 1),), ramp_time=1.0))
    assert windows.publishing(99) == {2} and windows.publishing(100) == {1, 2}
    assert windows.publishing(249) == {1, 2} and windows.publishing(250) == {1}
    assert all(windows.publishing(k) == {1} for k in (299, 300, 301, 10_000))


def test_a_schedule_is_steps_with_plus_and_minus_names_in_increasing_order():
    """'600 +ipc_h1 -ipc_h2' parses; a word without + or -, or steps out of order, is refused by name."""
    first, second = parse_schedule(["600 +ipc_h1", "900 +ipc_h1_retuned -ipc_h1"])
    assert (first.step, first.activate, second.deactivate) == (600, ("ipc_h1",), ("ipc_h1",))
    with pytest.raises(SwitchRefused, match="expected \\+NAME or -NAME, found 'ipc_h1'"):
        parse_schedule(["10 ipc_h1"])
    with pytest.raises(SwitchRefused, match="steps must increase"):
        parse_schedule(["900 +a", "600 -a"])
