"""Switch semantics (ros2_control's STRICT / BEST_EFFORT, one active claimant per command interface, only
interfaces the loop assembler can assemble) and who publishes which interface when."""
import math
from functools import partial

import pytest

from hawt_controllers.plugins.loop_assembly import assembly_problem
from hawt_controllers.plugins.switching import (ControllerInfo, InterfaceWindows, Switch, SwitchRefused, parse_schedule,
                                        plan_switch, ramp_steps)

CPC = ControllerInfo("/wt1/cpc", "cpc", ("collective_pitch", "generator_torque"), "active", switchable=False)


def _info(name, interfaces, state, **more):
    return ControllerInfo(f"/wt1/{name}", more.pop("type", "ipc"), tuple(interfaces), state,
                          publishing_until=more.pop("publishing_until", math.inf if state == "active" else 0.0),
                          **more)


def _controllers(**states):
    """cpc plus one ipc controller per keyword; ``ipc_h<n>...`` claims ``harmonic/<n>``."""
    infos = {CPC.name: CPC}
    for name, state in states.items():
        infos[f"/wt1/{name}"] = _info(name, (f"harmonic/{int(name[5])}",), state)
    return infos


def _claims(infos):
    return tuple((c.name, c.interfaces) for c in infos)


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


def test_a_second_active_claimant_of_an_interface_is_refused_but_a_swap_is_allowed():
    """Activating ipc_h1b while ipc_h1a holds harmonic/1 is refused naming both; activating it while deactivating
    ipc_h1a is a swap (harmonic/1 is handed over)."""
    controllers = _controllers(ipc_h1a="active", ipc_h1b="inactive")
    with pytest.raises(SwitchRefused, match="^/wt1/ipc_h1b: /wt1/ipc_h1a is the active claimant of harmonic/1"):
        plan_switch(controllers, ["ipc_h1b"], [], strict=True, step=10)
    incoming, outgoing, _ = plan_switch(controllers, ["ipc_h1b"], ["ipc_h1a"], strict=True, step=10)
    switch = Switch(10, _claims(incoming), _claims(outgoing))
    assert switch.replaced("harmonic/1") and switch.replaces(("harmonic/1",))
    assert not switch.replaced("harmonic/2") and switch.names() == ("/wt1/ipc_h1b", "/wt1/ipc_h1a")


def test_two_incoming_controllers_with_a_conflicting_claim_are_refused_naming_both():
    """Two inactive controllers that both claim blade_pitch (one of them also harmonic/2) cannot come in together:
    the refusal names both controllers and the interface; either alone may."""
    controllers = _controllers()
    controllers["/wt1/blade_sine"] = _info("blade_sine", ("blade_pitch",), "inactive", type="blade_sine")
    controllers["/wt1/custom"] = _info("custom", ("harmonic/2", "blade_pitch"), "inactive", type="custom")
    with pytest.raises(SwitchRefused) as refused:
        plan_switch(controllers, ["blade_sine", "custom"], [], strict=True, step=10)
    message = str(refused.value)
    assert "/wt1/blade_sine" in message and "/wt1/custom" in message and "blade_pitch" in message
    for name in ("blade_sine", "custom"):
        assert [c.name for c in plan_switch(controllers, [name], [], strict=True, step=10)[0]] == [f"/wt1/{name}"]


def test_a_claim_conflicting_with_an_active_controller_of_several_interfaces_is_refused_naming_both():
    """A controller claiming harmonic/2 cannot come in while ipc_h2 (active) holds it, whatever else it claims."""
    controllers = _controllers(ipc_h2="active")
    controllers["/wt1/custom"] = _info("custom", ("blade_pitch", "harmonic/2"), "inactive", type="custom")
    with pytest.raises(SwitchRefused, match="/wt1/custom: /wt1/ipc_h2 is the active claimant of harmonic/2"):
        plan_switch(controllers, ["custom"], [], strict=True, step=10)


def test_an_interface_the_loop_assembler_cannot_assemble_is_refused():
    """harmonic/1 cannot be assembled for B=1 (no inverse MBC; B=2 has one: Zalkind & Pao's θ_2 = −θ_1), a
    misspelled blade_pitchh is no interface at all: both activations are refused with the assembler's reason;
    harmonic/1 for B=3 is fine."""
    controllers = _controllers(ipc_h1="inactive")
    controllers["/wt1/blade_sine"] = _info("blade_sine", ("blade_pitchh",), "inactive", type="blade_sine")
    with pytest.raises(SwitchRefused, match="^/wt1/ipc_h1: cannot be assembled: harmonic/1: "):
        plan_switch(controllers, ["ipc_h1"], [], strict=True, step=10, assembly_problem=partial(assembly_problem,
                                                                                              blades=1))
    with pytest.raises(SwitchRefused, match="^/wt1/blade_sine: cannot be assembled: blade_pitchh: no such command "
                                            "interface \\(did you mean blade_pitch\\?\\)"):
        plan_switch(controllers, ["blade_sine"], [], strict=True, step=10,
                    assembly_problem=partial(assembly_problem, blades=3))
    three = partial(assembly_problem, blades=3)
    incoming, _, skipped = plan_switch(controllers, ["ipc_h1", "blade_sine"], [], strict=False, step=10,
                                       assembly_problem=three)
    assert [c.name for c in incoming] == ["/wt1/ipc_h1"] and "blade_pitchh" in skipped[0]


def test_deactivating_a_controller_is_not_checked_for_assembly():
    """A controller that is active can always be switched off, whatever the assembler says of its interface."""
    controllers = _controllers(ipc_h1="active")
    _, outgoing, _ = plan_switch(controllers, [], ["ipc_h1"], strict=True, step=10,
                                 assembly_problem=partial(assembly_problem, blades=2))
    assert [c.name for c in outgoing] == ["/wt1/ipc_h1"]


def test_a_controller_cannot_come_in_while_another_still_ramps_out_its_interface():
    """The outgoing contribution must reach zero before another claimant of that interface publishes."""
    controllers = _controllers(ipc_h1b="inactive")
    controllers["/wt1/ipc_h1a"] = _info("ipc_h1a", ("harmonic/1",), "inactive", publishing_until=250)
    with pytest.raises(SwitchRefused, match="still ramps out harmonic/1 until step 250"):
        plan_switch(controllers, ["ipc_h1b"], [], strict=True, step=200)
    assert plan_switch(controllers, ["ipc_h1b"], [], strict=True, step=250)[0]


def test_the_collective_controller_cannot_be_switched_off_only_swapped():
    """Deactivating cpc alone is refused with the reason (the safety system would stop the turbine); a swap for
    another claimant of collective_pitch and generator_torque is accepted, and so is the swap back."""
    with pytest.raises(SwitchRefused, match="cpc controller can only be swapped .* not switched off"):
        plan_switch(_controllers(), [], ["cpc"], strict=True, step=10)
    controllers = {**_controllers(), "/wt1/rpd": _info("rpd", CPC.interfaces, "inactive", type="repetitive_cpc",
                                                       switchable=False)}
    incoming, outgoing, _ = plan_switch(controllers, ["rpd"], ["cpc"], strict=True, step=10)
    assert [c.name for c in incoming] == ["/wt1/rpd"] and [c.name for c in outgoing] == ["/wt1/cpc"]
    swapped = {**controllers, "/wt1/cpc": _info("cpc", CPC.interfaces, "inactive", type="cpc", switchable=False),
               "/wt1/rpd": _info("rpd", CPC.interfaces, "active", type="repetitive_cpc", switchable=False)}
    assert plan_switch(swapped, ["cpc"], ["rpd"], strict=True, step=20)[0][0].name == "/wt1/cpc"


def test_ramp_steps_is_the_number_of_steps_the_output_takes_to_reach_zero():
    """ceil(ramp_time / dt): 1 s at 100 Hz is 100 steps, 0.015 s is 2, 0 is 0."""
    assert (ramp_steps(1.0, 0.01), ramp_steps(0.015, 0.01), ramp_steps(0.0, 0.01)) == (100, 2, 0)
    with pytest.raises(SwitchRefused, match="ramp_time"):
        ramp_steps(math.nan, 0.01)


def test_windows_follow_activation_ramp_out_and_swap():
    """h1 publishes from its activation; h2 until its ramp ends; a swap of h1 leaves no gap."""
    h1, h2 = "harmonic/1", "harmonic/2"
    windows = InterfaceWindows([h2], dt=0.01)
    windows.apply(Switch(100, activate=(("/a", (h1,)),), ramp_time=1.0))
    windows.apply(Switch(200, deactivate=(("/b", (h2,)),), ramp_time=0.5))
    windows.apply(Switch(300, activate=(("/c", (h1,)),), deactivate=(("/a", (h1,)),), ramp_time=1.0))
    assert windows.publishing(99) == {h2} and windows.publishing(100) == {h1, h2}
    assert windows.publishing(249) == {h1, h2} and windows.publishing(250) == {h1}
    assert all(windows.publishing(k) == {h1} for k in (299, 300, 301, 10_000))
    assert windows.interfaces() == {h1, h2}


def test_windows_of_a_controller_with_several_interfaces_and_of_one_that_starts_active():
    """blade_pitch starts with its announcement at step 50; a controller claiming two interfaces ramps both out."""
    windows = InterfaceWindows([], dt=0.01)
    windows.start(["blade_pitch"], step=50)
    windows.apply(Switch(100, activate=(("/m", ("harmonic/3", "harmonic/4")),)))
    windows.apply(Switch(200, deactivate=(("/m", ("harmonic/3", "harmonic/4")),), ramp_time=0.1))
    assert windows.publishing(49) == set() and windows.publishing(50) == {"blade_pitch"}
    assert windows.publishing(209) == {"blade_pitch", "harmonic/3", "harmonic/4"}
    assert windows.publishing(210) == {"blade_pitch"}


def test_a_schedule_is_steps_with_plus_and_minus_names_in_increasing_order():
    """'600 +ipc_h1 -ipc_h2' parses; a word without + or -, or steps out of order, is refused by name."""
    first, second = parse_schedule(["600 +ipc_h1", "900 +ipc_h1_retuned -ipc_h1"])
    assert (first.step, first.activate, second.deactivate) == (600, ("ipc_h1",), ("ipc_h1",))
    with pytest.raises(SwitchRefused, match="expected \\+NAME or -NAME, found 'ipc_h1'"):
        parse_schedule(["10 ipc_h1"])
    with pytest.raises(SwitchRefused, match="steps must increase"):
        parse_schedule(["900 +a", "600 -a"])
