"""The plant's parameter table and the model it builds from it, shared by the plant node and the in-process runner.

:func:`make_plant` turns the plant's parameter values into the turbine, its model in the
configured wind, and the model's output at the operating point of step 0 — the same for
every engine, so the same parameters give the same run.

The five aerodynamic options (``tower_shadow``, ``tower_drag``, ``skewed_wake``,
``unsteady_airfoil``, ``dynamic_inflow``) are ``turbine`` by default: the turbine definition's
(its ``aerodynamics`` section, :class:`hawt_plant.turbine.AerodynamicOptions`); ``true`` or
``false`` overrides it (:func:`aerodynamic_options`). ROS parameters are typed, so these rows are
dynamically typed with the choices ``turbine``, ``true``, ``false``: ``-p plant.skewed_wake:=true``
works in every engine, and anything else is refused before a graph starts.
"""
import math
from typing import TYPE_CHECKING, Any, Callable, Mapping, Tuple

from hawt_core.node_role import NodeRole
from hawt_core.parameter_table import ParameterError, ParameterSpec
from hawt_core.step_sync import RESEND_PERIOD
from hawt_plant.faults import parse_faults
from hawt_plant.inflow import PARKED_WIND_KINDS, WIND_KINDS, InflowSettings, make_wind
from hawt_plant.rotor_state import ROTOR_STATES
from hawt_plant.safety_system import Protection, SafetySettings, SafetySystem
from hawt_plant.turbine import AERODYNAMIC_OPTIONS, AerodynamicOptions, Turbine, nrel_5mw, turbine_from
from hawt_plant.turbulence import REFERENCE_WIND_SPEED, TURBULENCE_MODELS

if TYPE_CHECKING:
    from hawt_plant.model import TurbineModel, TurbineOutput

__all__ = ["DESCRIPTION", "DESCRIPTION_PARAMETERS", "PARAMETERS", "PLANT", "TURBINE", "aerodynamic_options", "aerodynamics_line", "check_parameters", "make_plant",
           "make_safety_system"]

TURBINE = "turbine"
"""The value of an aerodynamic option's parameter that takes the turbine definition's option."""
MAX_DURATION = 1e6
"""Longest simulated time a parameter may name [s]: eleven days, far beyond any load case."""
MAX_OPERATING_YAW = math.radians(45.0)
"""Largest yaw misalignment [rad] of an operating rotor: blade-element momentum theory with a skewed-wake correction
is not made for more (IEC 61400-1's operating cases ask at most 30 deg); an idling or parked rotor takes any."""


def _aerodynamic_option(name: str, description: str) -> ParameterSpec:
    return ParameterSpec(name, TURBINE, f"{description}; turbine: the turbine definition's (its aerodynamics "
                         "section), true or false: on or off whatever the turbine says", choices=(TURBINE, True, False),
                         read_only=True)


PARAMETERS = (
    ParameterSpec("turbine_file", "", "turbine definition YAML, or a packaged turbine's name: nrel_5mw, "
                  "nrel_5mw_two_bladed, nrel_5mw_two_bladed_downwind ('' = the packaged NREL 5 MW)", read_only=True),
    ParameterSpec("dt", 0.01, "plant step (100 Hz by default)", "s", minimum=1e-3, maximum=0.1, read_only=True),
    ParameterSpec("mode", "lockstep", "timing mode", choices=("lockstep", "realtime"), read_only=True),
    ParameterSpec("duration", 0.0, "simulated time after which the plant stops (0: run until stopped)", "s",
                  minimum=0.0, maximum=MAX_DURATION, read_only=True),
    ParameterSpec("wind_type", "steady", "inflow model: steady, turbulent, bts, a step, or an IEC 61400-1 extreme "
                  "condition: eog, edc (direction change), ecd (coherent gust with direction change), ews_vertical, "
                  "ews_horizontal (wind shear), and for an idling or parked rotor ewm50, ewm1 (steady extreme wind, "
                  "50- and 1-year, of wind_class)", choices=WIND_KINDS, read_only=True),
    ParameterSpec("yaw_misalignment", 0.0, "angle of the wind from the rotor's shaft axis, positive towards +y (left "
                  "looking downwind), the nacelle yawed the other way; at most 45 deg (0.785 rad) for an operating "
                  "rotor", "rad", minimum=-math.pi, maximum=math.pi, read_only=True),
    ParameterSpec("rotor", "operating", "operating: runs on the commands; idling, parked: shut down (IEC DLC 6.x), "
                  "blades held at feather, generator off the grid, commands checked but not applied, no induction; "
                  "parked: a brake holds the generator at rest", choices=ROTOR_STATES, read_only=True),
    ParameterSpec("wind_speed", 18.0, "mean hub-height wind speed", "m/s",
                  minimum=3.0, maximum=30.0, read_only=True),
    ParameterSpec("shear_exponent", 0.2, "power-law shear exponent alpha", minimum=-0.5, maximum=0.99,
                  read_only=True),
    ParameterSpec("turbulence_class", "B", "IEC turbulence category", choices=("A", "B", "C"), read_only=True),
    ParameterSpec("turbulence_model", "NTM", "wind_type turbulent: IEC normal or extreme turbulence model (the ETM's "
                  "sigma_1 grows with wind_class's annual mean speed)", choices=TURBULENCE_MODELS, read_only=True),
    ParameterSpec("wind_class", "I", "IEC wind turbine class, its reference speed V_ref 50, 42.5 or 37.5 m/s: the "
                  "ETM's annual mean speed, the EOG's 1-year extreme wind and the EWM's",
                  choices=tuple(REFERENCE_WIND_SPEED), read_only=True),
    ParameterSpec("seed", 0, "seed of the turbulent field", minimum=0, maximum=2**31 - 1, read_only=True),
    ParameterSpec("field_duration", 600.0, "length of the turbulent field (wraps after)", "s", minimum=10.0,
                  maximum=7200.0, read_only=True),
    ParameterSpec("bts_file", "", "TurbSim .bts file for wind_type bts", read_only=True),
    ParameterSpec("step_speed", 14.0, "wind_type step: hub speed after the step", "m/s", minimum=0.0,
                  maximum=40.0, read_only=True),
    ParameterSpec("step_time", 20.0, "wind_type step, eog, edc, ecd, ews_*: time of the step or gust start", "s",
                  minimum=0.0, maximum=MAX_DURATION, read_only=True),
    ParameterSpec("gust_sign", 1, "wind_type edc, ecd: +1 turns the wind towards +y (left looking downwind), -1 "
                  "towards -y; ews_vertical, ews_horizontal: +1 faster above the hub or at +y, -1 the opposite",
                  minimum=-1, maximum=1, choices=(1, -1), read_only=True),
    _aerodynamic_option("tower_shadow", "tower shadow on the blade elements: potential flow (and, behind the "
                        "tower of a downwind rotor, Powles' wake)"),
    _aerodynamic_option("tower_drag", "aerodynamic drag on the tower (AeroDyn TwrAero)"),
    _aerodynamic_option("dynamic_inflow", "Oye dynamic inflow instead of quasi-steady induction"),
    _aerodynamic_option("skewed_wake", "Pitt-Peters skewed-wake correction of the axial induction (AeroDyn "
                        "Skew_Mod 1, SkewRedistr_Mod 1)"),
    _aerodynamic_option("unsteady_airfoil", "unsteady airfoil aerodynamics: Hansen-Gaunaa-Madsen dynamic stall on "
                        "the elements whose polar has unsteady parameters (AeroDyn UA_Mod 4)"),
    ParameterSpec("torque_disturbance", 0.0, "amplitude D of an unmeasured disturbance D sin(azimuth) on the "
                  "generator torque acting on the drivetrain (Fratini R4)", "N*m", minimum=0.0, maximum=20000.0,
                  read_only=True),
    ParameterSpec("initial_azimuth", 0.0, "azimuth of blade 1 at time 0", "rad", minimum=0.0,
                  maximum=2 * math.pi, read_only=True),
    ParameterSpec("resend_period", RESEND_PERIOD, "lockstep: wall time after which an unanswered step is sent again", "s",
                  minimum=0.01, maximum=60.0),
    ParameterSpec("wait_for_subscribers", 0, "send the first step only once plant/blade_loads has this many "
                  "subscribers (a recorder or test that must see every step)", minimum=0, maximum=1000,
                  read_only=True),
    ParameterSpec("wait_for_recorder", False, "send the first step only once the node hawt_recorder subscribes "
                  "to every topic that has a publisher (at most 10 s); hawt launch --record sets it",
                  read_only=True),
    ParameterSpec("recorder_window", 5.0, "lockstep: simulated time the plant may run ahead of what the recorder "
                  "has written of its plant/blade_loads (/recorder/progress); it holds the next step until the "
                  "recorder catches up, so a recording is complete at any load (0: never hold)", "s", minimum=0.0,
                  maximum=600.0, read_only=True),
    ParameterSpec("recorder_timeout", 10.0, "lockstep: wall time a held plant waits on a recorder that writes "
                  "nothing more before it goes on without it (a recorder event says so); not with "
                  "recorder_required", "s", minimum=0.1, maximum=3600.0, read_only=True),
    ParameterSpec("recorder_required", False, "lockstep: a held plant waits for its recorder however long it "
                  "takes, never going on without it (hawt launch --record sets it and respawns a recorder that "
                  "dies; --record-optional does not)", read_only=True),
    ParameterSpec("report_period", 10.0, "simulated time between progress lines", "s", minimum=0.1,
                  maximum=MAX_DURATION),
    ParameterSpec("command_timeout", 3.0, "wall time without an applied command (lockstep: the current step "
                  "unanswered, resends included; must exceed resend_period) after which the safety system trips "
                  "and feathers", "s", minimum=0.01, maximum=600.0, read_only=True),
    ParameterSpec("startup_timeout", 90.0, "wall time the first command may take once the plant has started "
                  "(controllers starting up) before the safety system trips", "s", minimum=0.01, maximum=3600.0,
                  read_only=True),
    ParameterSpec("command_sources", ["mbc"], "the nodes whose control/pitch_command the plant obeys (names "
                  "relative to its namespace, or absolute); another publisher's commands are refused and reported "
                  "as an intruder (['']: obey any publisher)", read_only=True),
    ParameterSpec("faults", [""], "faults injected at a step, one entry each 'KIND key=value ... at=T' (T [s], a whole "
                  "number of steps): load_bias blade=B moment=N*m, load_gain blade=B factor=F, load_frozen blade=B, "
                  "load_dead blade=B, azimuth_offset angle=RAD, pitch_stuck blade=B, pitch_runaway blade=B "
                  "to=feather|fine, grid_loss (hawt_plant.faults)", read_only=True),
    ParameterSpec("stale_burst_gap", 1.0, "realtime: commands older than the last applied one are reported once "
                  "per burst; a burst ends after this long without one", "s", minimum=0.0, maximum=600.0,
                  read_only=True),
)



def check_parameters(values: Mapping[str, Any]) -> None:
    """The plant's rules across parameters (each value already checked against its row) and its faults' entries
    (their blades against the turbine's, if it loads: a turbine_file that does not is named by
    hawt_tools.parameter_check), without building the model; ParameterError if broken."""
    if values["rotor"] == "operating":
        if values["wind_type"] in PARKED_WIND_KINDS:
            raise ParameterError(f"wind_type: {values['wind_type']} is the extreme wind of a shut-down turbine: set "
                                 "rotor to idling or parked")
        if abs(values["yaw_misalignment"]) > MAX_OPERATING_YAW:
            raise ParameterError(f"yaw_misalignment: {values['yaw_misalignment']:g} rad "
                                 f"({math.degrees(values['yaw_misalignment']):.1f} deg) is beyond the "
                                 f"{math.degrees(MAX_OPERATING_YAW):g} deg an "
                                 "operating rotor's blade-element momentum theory takes; set rotor to idling or parked "
                                 "for a shut-down turbine")
    if values["mode"] == "lockstep" and values["command_timeout"] <= values["resend_period"]:
        raise ParameterError(f"command_timeout: {values['command_timeout']} s must exceed resend_period "
                             f"{values['resend_period']} s in lockstep (a step is resent before the safety system "
                             "trips)")
    if any(fault.blade for fault in parse_faults(values["faults"], values["dt"])):
        try:
            blades = turbine_from(values["turbine_file"] or "nrel_5mw").rotor.number_of_blades
        except (OSError, ValueError):
            return
        parse_faults(values["faults"], values["dt"], blades)


PLANT = NodeRole("plant", PARAMETERS, check_parameters)
"""The plant node's role (entry point ``hawt.nodes: plant``)."""

DESCRIPTION_PARAMETERS = (
    ParameterSpec("turbine_file", "", "turbine definition YAML, its folder or a packaged turbine's name ('' = the "
                  "packaged NREL 5 MW)", read_only=True),
    ParameterSpec("dt", 0.01, "step of the measurements", "s", minimum=1e-3, maximum=0.1, read_only=True),
)
"""The parameters of the plant_description node (``plant/description`` without a simulated plant)."""

DESCRIPTION = NodeRole("description", DESCRIPTION_PARAMETERS)
"""The plant_description node's role (entry point ``hawt.nodes: plant_description``)."""


def aerodynamic_options(turbine: Turbine, values: Mapping[str, Any]) -> AerodynamicOptions:
    """The aerodynamic options a plant with the parameter ``values`` runs: the turbine's, except those whose
    parameter is true or false (their source then ``the plant's parameter NAME``)."""
    given = {name: values[name] for name in AERODYNAMIC_OPTIONS if values[name] != TURBINE}
    return turbine.aerodynamics.overridden(given, "the plant's parameter") if given else turbine.aerodynamics


def aerodynamics_line(turbine: Turbine, values: Mapping[str, Any]) -> str:
    """Which aerodynamic options the plant runs, for its start-up line: ``aerodynamics: tower_shadow on, ...,
    dynamic_inflow off (the turbine's; by parameter: skewed_wake)``."""
    given = [name for name in AERODYNAMIC_OPTIONS if values[name] != TURBINE]
    whose = "the turbine's" + (f"; by parameter: {', '.join(given)}" if given else "")
    return f"aerodynamics: {aerodynamic_options(turbine, values).text()} ({whose})"


def make_plant(values: Mapping[str, Any], progress: Callable[[str], None] = lambda _: None
               ) -> Tuple[Turbine, "TurbineModel", "TurbineOutput"]:
    """The turbine, its model and the output of step 0 for the plant's parameter ``values``; the aerodynamic
    options are :func:`aerodynamic_options`. ``progress`` gets the lines of a turbulent field's generation (what,
    where it is cached, how long it took)."""
    from hawt_plant.model import ModelConfig, TurbineModel  # numba's: not for hawt launch's parameter check

    v = values
    turbine = turbine_from(v["turbine_file"]) if v["turbine_file"] else nrel_5mw()
    wind = make_wind(InflowSettings(
        kind=v["wind_type"], wind_speed=v["wind_speed"], shear_exponent=v["shear_exponent"],
        hub_height=turbine.hub_height, rotor_radius=turbine.rotor.tip_radius,
        turbulence_class=v["turbulence_class"], turbulence_model=v["turbulence_model"],
        turbine_class=v["wind_class"], seed=v["seed"], field_duration=max(v["field_duration"], v["duration"]),
        bts_file=v["bts_file"], step_speed=v["step_speed"], step_time=v["step_time"], gust_sign=v["gust_sign"],
        yaw_misalignment=v["yaw_misalignment"]), progress)
    if v["rotor"] != "operating":
        progress(f"rotor {v['rotor']}: blades at feather, generator off the grid"
                 + (", brake on" if v["rotor"] == "parked" else "") + "; the controllers' commands are not applied")
    options = aerodynamic_options(turbine, v)
    model = TurbineModel(turbine, wind, ModelConfig(
        dt=v["dt"], torque_disturbance=v["torque_disturbance"], rotor=v["rotor"],
        **{name: getattr(options, name) for name in AERODYNAMIC_OPTIONS}), azimuth=v["initial_azimuth"])
    return turbine, model, model.output


def make_safety_system(turbine: Turbine, values: Mapping[str, Any]) -> SafetySystem:
    """The plant's safety chain: its watchdog's timeouts from ``values``, the turbine's protection levels, feathering
    at the turbine's pitch actuator limits (the same in every engine)."""
    actuator = turbine.pitch_actuator
    return SafetySystem(SafetySettings(values["command_timeout"], values["startup_timeout"], actuator.max_angle,
                                       actuator.max_rate), Protection(turbine.protection, values["dt"]))
