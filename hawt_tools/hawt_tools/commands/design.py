"""The plant's models and controller design on them: ``hawt coupling`` (Disario's azimuth offset), ``hawt
linearize`` (Coleman-frame linear models over the power curve), ``hawt design lqg|cpc|ipc``."""
import argparse
import json
import math
import os
import time
from pathlib import Path
from typing import Sequence

from hawt_tools.commands.options import NOT_NEGATIVE, POSITIVE, output_path, plant_overrides, progress, within
from hawt_tools.graph_file import GraphError


def _cmd_coupling(args: argparse.Namespace) -> int:
    """Disario's azimuth offset per wind speed and harmonic, from the plant's measured response."""
    from hawt_controllers.design.ipc_design import coupling_survey
    from hawt_plant.turbine import nrel_5mw

    if args.bag:
        return _coupling_identified(args)
    for v in args.wind_speeds:
        if not 3.0 <= v <= 30.0:
            raise GraphError(f"--wind-speeds: {v:g} m/s is outside the plant's 3..30 m/s")
    for n in args.harmonics:
        if not 1 <= n <= 4:
            raise GraphError(f"--harmonics: {n} is outside 1..4")
    points = coupling_survey(nrel_5mw(), args.wind_speeds, args.harmonics, progress=progress)
    rows = [{"wind_speed": p.response.wind_speed, "harmonic": p.response.harmonic,
             "collective_pitch_deg": math.degrees(p.response.collective_pitch),
             "rotor_speed_rpm": p.response.rotor_speed * 30 / math.pi, "sensitivity": p.response.sensitivity,
             "offset_deg": math.degrees(p.offset), "cross_gain": p.cross_gain, "rga": p.rga,
             "time_constant": p.time_constant} for p in points]
    if args.json:
        print(json.dumps(rows))
        return 0
    print("NREL 5 MW, uniform wind, open loop (generator torque held): the phase offset phi_n = n psi_n that "
          "decouples tilt from yaw at DC")
    print("(Disario 2018: 19 deg at 25 m/s, 12.1 rpm, for FAST's NREL 5 MW)")
    print(f"{'wind m/s':>8s} {'n':>2s} {'pitch deg':>9s} {'rpm':>6s} {'dM/dtheta MN*m/rad':>19s} {'offset deg':>10s} "
          f"{'|P21/P11| at 0':>14s} {'RGA11 at 0':>10s} {'tau s':>6s}")
    for row in rows:
        print(f"{row['wind_speed']:8.1f} {row['harmonic']:2d} {row['collective_pitch_deg']:9.2f} "
              f"{row['rotor_speed_rpm']:6.2f} {row['sensitivity'] / 1e6:19.2f} {row['offset_deg']:10.1f} "
              f"{row['cross_gain']:14.3f} {row['rga']:10.3f} {row['time_constant']:6.3f}")
    return 0


def _coupling_identified(args: argparse.Namespace) -> int:
    """``hawt coupling --bag``: the tilt/yaw plant identified from a recorded excitation run."""
    from hawt_analysis.identification import identify_coleman_plant

    progress(f"identifying the Coleman-frame plant of harmonic {args.harmonics[0]} from {args.bag}")
    found = identify_coleman_plant(args.bag, args.harmonics[0], args.namespace)
    row = {"offset_deg": math.degrees(found.offset), "band_offset_deg": math.degrees(found.band_offset),
           "coherence": found.coherence}
    if args.json:
        print(json.dumps(row))
        return 0
    print(f"{args.bag}, harmonic {args.harmonics[0]}, identified by cross-spectra: the offset that decouples tilt "
          f"from yaw at low frequency {row['offset_deg']:.1f} deg; the one that minimises the mean |P12| over "
          f"0.1-1 rad/s {row['band_offset_deg']:.1f} deg (coherence there >= {found.coherence:.2f}; "
          "Disario: 19 deg at 25 m/s)")
    return 0


def _cmd_linearize(args: argparse.Namespace) -> int:
    """The plant's linear models in the Coleman frame per wind speed, the modes table and the Campbell diagram."""
    from hawt_controllers.laws.coleman_models import save_models
    from hawt_controllers.design.linear_models import campbell_figure, linearize_power_curve, model_summary

    for v in args.wind_speeds:
        if not 3.0 <= v <= 30.0:
            raise GraphError(f"--wind-speeds: {v:g} m/s is outside the plant's 3..30 m/s")
    if not 1 <= args.azimuths <= 360:
        raise GraphError(f"--azimuths: {args.azimuths} is outside 1..360")
    if not 0.0 <= args.settle <= 3600.0:
        raise GraphError(f"--settle: {args.settle:g} s is outside 0..3600 s")
    plant = plant_overrides(args.arguments)
    inflow = plant.get("dynamic_inflow")
    if inflow == "turbine":  # the turbine's own option, which the linear models cannot take either when it is on
        from hawt_plant.turbine import turbine_from

        inflow = turbine_from(str(plant.get("turbine_file") or "nrel_5mw")).aerodynamics.dynamic_inflow
    if inflow is True:
        raise GraphError("dynamic_inflow:=true: the linear models have quasi-steady aerodynamics (no inflow states "
                         "yet); linearise without it")
    output = output_path(args.output, "--output")
    progress(f"linearizing at {len(args.wind_speeds)} wind speed(s), {args.azimuths} azimuths each, "
             f"{args.workers} worker(s)")
    start = time.monotonic()

    def done(model, count: int, total: int) -> None:
        progress(f"{model.wind_speed:g} m/s done in {model.seconds:.1f} s ({count}/{total})")

    models = linearize_power_curve(args.wind_speeds, args.azimuths, args.settle, plant, args.workers, done)
    save_models(output, models)
    print(f"{len(models)} models ({models[0].loops}; states, inputs and outputs in the Coleman frame, averaged over "
          f"{args.azimuths} azimuths) written to {output} in {time.monotonic() - start:.1f} s")
    print("per wind speed: rotor speed, pitch, dM_cos/dtheta_cos at DC, Disario's 1P offsets: decoupling at DC from "
          "the pitch command (the IPC design's) and from the pitch angle, and minimising the mean |P12| over "
          "0.1-1 rad/s from the angle (Disario: 19 deg at 25 m/s for FAST's NREL 5 MW); then each oscillating "
          "mode: its dominant state, frequency [Hz]/damping ratio")
    for model in models:
        summary = model_summary(model.model)
        modes = "  ".join(f"{m.state} {m.frequency:.3f}/{m.damping:.3f}" for m in summary.modes)
        offsets = [math.degrees(offset) for offset in summary.offsets]
        print(f"{model.wind_speed:5.1f} m/s  {model.rotor_speed * 30 / math.pi:5.2f} rpm  pitch "
              f"{math.degrees(model.pitch):5.2f} deg  {summary.gain / 1e6:7.2f} MN*m/rad  offsets {offsets[0]:4.1f} "
              f"{offsets[1]:4.1f} {offsets[2]:4.1f} deg  {modes}")
    if args.plot:
        campbell_figure(models, Path(args.plot))
        print(f"Campbell diagram: {args.plot}")
    return 0


def _cmd_design_lqg(args: argparse.Namespace) -> int:
    """Selvam's FB-FF IPC designed on the plant's linear model at one wind speed: checks and closed-loop shape."""
    from hawt_core.exceptions import ConfigurationError
    from hawt_controllers.design.lqg_tuning import lqg_tuning
    from hawt_controllers.laws.coleman_models import load_models
    from hawt_controllers.plugins.lqg_ipc import DEFAULT_MODELS
    from hawt_controllers.laws.lqg_design import LqgWeights
    from hawt_controllers.laws.lqg_ipc import frequency_response_figure

    path = Path(args.linear_models) if args.linear_models else DEFAULT_MODELS
    if not path.is_file():
        raise GraphError(f"--linear-models: {path}: no such file (write one with hawt linearize)")
    models = {m.wind_speed: m for m in load_models(path)}
    if args.wind_speed not in models:
        raise GraphError(f"--wind-speed: {args.wind_speed:g} m/s is not in {path} (it has "
                         f"{', '.join(f'{v:g}' for v in sorted(models))})")
    model = models[args.wind_speed]
    try:
        weights = LqgWeights(**{name: getattr(args, name) for name in
                                ("measurement_noise", "wind_walk", "input_weight", "inversion_walk")
                                if getattr(args, name) is not None})
        tuning = lqg_tuning(model, args.dt, weights)
    except ConfigurationError as error:
        raise GraphError(str(error)) from None
    n = tuning.design.states
    print(f"LQG FB-FF IPC (Selvam 2009) at {args.wind_speed:g} m/s from {path}, dt {args.dt:g} s, loops "
          f"{model.loops}; weights {tuning.weights}")
    print(f"observability of the augmented model (with the wind states): rank {tuning.observability_rank} of "
          f"{n + 2}; controllability of the turbine states: rank {tuning.controllability_rank} of {n}")
    print(f"SDMI inverse: spectral radius {tuning.inverse_radius:.6f} (stable below 1)")
    print("closed loop |u_cos -> M_cos| / |u_sin -> M_sin| [MN*m per m/s]:")
    print(f"{'':16s}" + "".join(f"{name:>20s}" for name in tuning.frequencies))
    for label, kind in (("no IPC", "none"), ("integrator IPC", "integrator"), ("FB-FF (LQG)", "lqg")):
        response = tuning.responses[kind]
        print(f"{label:16s}" + "".join(f"{response[k, 0, 0]:10.3f}/{response[k, 1, 1]:<9.3f}"
                                         for k in range(len(tuning.frequencies))))
    if args.plot:
        frequency_response_figure(tuning.design, Path(args.plot), model.rotor_speed, *tuning.integrator_gains)
        print(f"frequency responses: {args.plot}")
    return 0


def _cmd_design_cpc(args: argparse.Namespace) -> int:
    """The baseline collective controller tuned from a turbine definition (Jonkman's method), its schedule and a
    comparison with Jonkman's NREL 5 MW tuning or a ROSCO DISCON.IN."""
    from hawt_controllers.design.cpc_design import (design_collective, discon_comparison, format_comparison, format_design,
                                             jonkman_comparison, write_design)
    from hawt_core.exceptions import ConfigurationError
    from hawt_controllers.discon.rosco_input import read_settings
    from hawt_controllers.design.tunings import tuning_path, turbine_folder
    from hawt_plant.turbine import TurbineDefinitionError, turbine_from

    if args.discon and not Path(args.discon).is_file():
        raise GraphError(f"--discon: {args.discon}: no such file")
    if args.output:
        output_path(args.output, "-o")
    try:
        turbine = turbine_from(args.turbine)
        design = design_collective(turbine, args.natural_frequency, args.damping)
        discon = discon_comparison(design, read_settings(Path(args.discon))) if args.discon else None
    except (TurbineDefinitionError, ConfigurationError) as error:
        raise GraphError(str(error)) from None
    print(format_design(design))
    if discon is not None:
        print(format_comparison(f"against {args.discon} (ROSCO's gains with their sign turned)", discon))
    elif args.turbine == "nrel_5mw":
        print(format_comparison("against Jonkman et al. (2009), hawt_controllers/data/nrel5mw_baseline.yaml",
                                jonkman_comparison(design)))
    folder = turbine_folder(args.turbine)
    output = args.output or (tuning_path(args.turbine, "cpc") if folder is not None else None)
    if output:
        try:
            path = write_design(design, output)
        except OSError as error:
            raise GraphError(f"-o: {error}") from None
        use = (f"hawt launch baseline turbine:={folder}" if not args.output else
               f"hawt launch baseline turbine:={args.turbine} -p cpc.controller_file:={path}")
        print(f"tuning: {path} (use it as: {use})")
    return 0


def _cmd_design_ipc(args: argparse.Namespace) -> int:
    """The IPC harmonics tuned from the plant, those past the actuator's rate budget written inactive, as the ipc
    graph's parameter file (hawt_controllers.design.ipc_design.write_tunings)."""
    from hawt_controllers.design.ipc_design import write_tunings
    from hawt_controllers.design.tunings import TuningError
    from hawt_plant.turbine import TurbineDefinitionError

    if args.linear_models and not Path(args.linear_models).is_file():
        raise GraphError(f"--linear-models: {args.linear_models}: no such file (write one with hawt linearize)")
    for option, path in (("-o", args.output), ("--retuned-output", args.retuned_output)):
        if path:
            output_path(path, option)
    try:
        write_tunings(args.turbine, args.harmonics, args.wind_speeds, args.reference_speed,
                      2 * math.pi * args.bandwidth_hz, args.loop_delay, args.dt,
                      args.linear_models and Path(args.linear_models), args.measured,
                      args.output and Path(args.output), args.retuned_output and Path(args.retuned_output),
                      args.retuned_only)
    except TurbineDefinitionError as error:
        raise GraphError(f"--turbine: {error}") from None
    except TuningError as error:
        raise GraphError(str(error)) from None
    return 0


def _add_coupling(commands: argparse._SubParsersAction) -> None:
    coupling = commands.add_parser(
        "coupling", help="the azimuth offset that decouples tilt from yaw, per wind speed and harmonic (Disario)",
        description="Measure the plant's non-rotating response to a static cyclic pitch demand per wind speed and "
                    "harmonic (open loop, the generator torque held) and give Disario's DC-decoupling phase offset "
                    "phi_n, the tilt/yaw cross gain and RGA11 without it, and the first-order blade time constant "
                    "with the same offset.")
    coupling.add_argument("--wind-speeds", type=float, nargs="+",
                          default=[5.0, 7.0, 9.0, 11.4, 13.0, 15.0, 18.0, 21.0, 25.0], help="[m/s]")
    coupling.add_argument("--harmonics", type=int, nargs="+", default=[1])
    coupling.add_argument("--bag", help="identify instead from a recorded run with coleman_excitation (the "
                                        "identification graph), for the first of --harmonics")
    coupling.add_argument("--namespace", help="the turbine (e.g. /wt1) when the bag holds several")
    coupling.add_argument("--json", action="store_true", help="print the rows as JSON")
    coupling.set_defaults(run=_cmd_coupling)


def _add_linearize(commands: argparse._SubParsersAction) -> None:
    linearize = commands.add_parser(
        "linearize", help="the plant's linear models in the Coleman frame per wind speed, its modes and Campbell "
                          "diagram",
        description="Linearise the plant (the plant node's defaults, changed by NAME:=VALUE; steady sheared wind) "
                    "about its periodic steady state with pitch and generator torque held (the collective and "
                    "torque loops open) at N azimuths per wind speed, by central differences of its "
                    "continuous-time dynamics with quasi-steady aerodynamics; transform each model to multi-blade "
                    "coordinates (Bir's MBC3) and average over azimuth. States: rotor and generator speed, shaft "
                    "torsion, tower-top fore-aft/side-side, blade flap (collective/cos/sin) and their rates, pitch "
                    "actuators. Inputs: pitch commands (collective/cos/sin), generator torque, blade-effective wind "
                    "changes "
                    "(collective/cos/sin). "
                    "Outputs: blade-root moments (collective/cos/sin), speeds, tower-top motion, hub tilt/yaw, "
                    "tower-base moments, thrust, aerodynamic torque. Load the file with "
                    "hawt_controllers.design.linear_models.load_models, or with numpy: "
                    "scipy.signal.StateSpace(a[k], b[k], c[k], d[k]) at wind_speeds[k].")
    linearize.add_argument("arguments", nargs="*", metavar="NAME:=VALUE", help="plant parameters, e.g. "
                                                                              "shear_exponent:=0.0")
    linearize.add_argument("--wind-speeds", type=float, nargs="+", default=[float(v) for v in range(5, 26)],
                           help="[m/s] (default 5 6 ... 25)")
    linearize.add_argument("--azimuths", type=int, default=12, help="azimuths per revolution (default 12)")
    linearize.add_argument("--settle", type=float, default=60.0, metavar="S",
                           help="simulated seconds to reach the periodic orbit first (default 60)")
    linearize.add_argument("--workers", type=int, default=os.cpu_count() or 1, help="processes (default: CPUs)")
    linearize.add_argument("--output", default="linear_models.npz", help="the models' file (.npz)")
    linearize.add_argument("--plot", metavar="PNG", help="write the Campbell diagram here")
    linearize.set_defaults(run=_cmd_linearize)


def _add_design(commands: argparse._SubParsersAction) -> None:
    design = commands.add_parser("design", help="design a controller on the plant's models (lqg, cpc, ipc)")
    design_commands = design.add_subparsers(dest="design", required=True, metavar="CONTROLLER")
    lqg = design_commands.add_parser(
        "lqg", help="Selvam's LQG IPC with wind-estimate feedforward: checks and closed-loop frequency responses",
        description="Design the lqg_ipc law at one wind speed on the plant's Coleman-frame linear model (the file of "
                    "hawt linearize; default the NREL 5 MW's shipped with hawt_controllers) as the node does at "
                    "start, print the observability, controllability and SDMI stability checks and the closed-loop "
                    "response from the cos/sin blade-effective wind to the cos/sin root moments for no IPC, the "
                    "integrator IPC (ipc_h1's tuning) and FB-FF, and plot them (Selvam's Figs 6-7).")
    lqg.add_argument("--wind-speed", type=float, default=18.0, help="[m/s], one of the file's (default 18)")
    lqg.add_argument("--linear-models", help="the .npz of hawt linearize")
    lqg.add_argument("--dt", type=float, default=0.01, help="controller step [s] (default 0.01)")
    for option, text in (("--measurement-noise", "Q_v [(MN*m)^2]"), ("--wind-walk", "Q_w intensity [(m/s)^2/s]"),
                         ("--input-weight", "R [deg^2]"), ("--inversion-walk", "Q_eta of the SDMI")):
        lqg.add_argument(option, type=float, help=f"{text} (default: lqg_ipc's)")
    lqg.add_argument("--plot", metavar="PNG", help="write the frequency responses here")
    lqg.set_defaults(run=_cmd_design_lqg)
    cpc = design_commands.add_parser(
        "cpc", help="the baseline collective controller tuned from a turbine definition (Jonkman's method)",
        description="Tune the cpc law (Jonkman et al. 2009 ch. 7) for a turbine from the plant's steady BEM and "
                    "modal model: the region-2 torque gain from the BEM's Cp-max and optimal tip-speed ratio, the "
                    "rated-speed pitch PI for a natural frequency and damping, gain-scheduled over pitch from the "
                    "frozen-wake pitch sensitivity of the region-3 points, the speed filter at 1/4 of the blade's "
                    "estimated edgewise mode. Print the schedule and compare it with Jonkman's tuning (for the "
                    "packaged nrel_5mw) or a ROSCO DISCON.IN (--discon); write it with -o.")
    cpc.add_argument("--turbine", default="nrel_5mw", metavar="T",
                     help="a turbine.yaml, its folder, or a packaged turbine's name (default nrel_5mw)")
    cpc.add_argument("-o", "--output", metavar="FILE", help="write the tuning here (the cpc's controller_file; "
                     "default for a turbine folder: its cpc.yaml, which its graphs use)")
    cpc.add_argument("--natural-frequency", type=float, default=0.6, metavar="W",
                     help="of the pitch loop [rad/s] (default 0.6, Jonkman's; ROSCO's IEA 15 MW: 0.2)")
    cpc.add_argument("--damping", type=float, default=0.7, metavar="Z",
                     help="damping ratio of the pitch loop (default 0.7, Jonkman's; ROSCO's IEA 15 MW: 1.0)")
    cpc.add_argument("--discon", metavar="DISCON.IN", help="compare with this ROSCO input's gains (e.g. the deck's)")
    cpc.set_defaults(run=_cmd_design_cpc)
    ipc = design_commands.add_parser(
        "ipc", help="the per-harmonic IPC (ipc_h1, ipc_h2, ...) tuned from the plant, for the ipc graph",
        description="Tune each IPC harmonic from the plant: dM/dtheta and the phase offset from the plant's "
                    "Coleman-frame linear models (the measured static response printed beside them as the "
                    "cross-check) or, with --measured or without models, from the measured static response; van "
                    "Engelen's integral gain for a 0.1 Hz crossover at --reference-speed, gain-scheduled over the "
                    "operating points. Print each harmonic's rate budget (the pitch rate that cancelling its moment of "
                    "steady wind with shear 0.2 takes, against the actuator's limit), leave active only the harmonics "
                    "that fit it together (1P first, up to 70 % of the rate limit), and write the ipc graph's "
                    "parameter file (the turbine's ipc tuning) with the others inactive, and the switching graph's "
                    "retuned 1P controller derived from it.")
    ipc.add_argument("--turbine", default="nrel_5mw", metavar="T",
                     help="a turbine.yaml, its folder, or a packaged turbine's name (default nrel_5mw); a folder's "
                          "tunings go beside it")
    ipc.add_argument("--harmonics", type=within(1, kind=int), nargs="+", default=[1, 2, 3], metavar="N",
                     help="the harmonics to design, each its ipc_hN node (default 1 2 3)")
    ipc.add_argument("--wind-speeds", type=POSITIVE, nargs="+", default=[13.0, 16.0, 18.0, 20.0, 24.0],
                     metavar="V", help="operating points above rated [m/s] (default 13 16 18 20 24)")
    ipc.add_argument("--reference-speed", type=POSITIVE, default=18.0, metavar="V",
                     help="where the gain is designed [m/s] (default 18)")
    ipc.add_argument("--bandwidth-hz", type=POSITIVE, default=0.1, metavar="F",
                     help="loop crossover [Hz] (default 0.1, van Engelen's)")
    ipc.add_argument("--loop-delay", type=NOT_NEGATIVE, default=0.1, metavar="S",
                     help="delay from measurement to pitch [s]: one plant step plus the pitch actuator's lag "
                          "(default 0.1)")
    ipc.add_argument("--dt", type=POSITIVE, default=0.01, metavar="S", help="controller step [s] (default 0.01)")
    ipc.add_argument("--linear-models", metavar="FILE.npz",
                     help="the plant's Coleman-frame models (hawt linearize; default: the turbine's, if it has them)")
    ipc.add_argument("--measured", action="store_true", help="the measured static response only, no linear models")
    ipc.add_argument("-o", "--output", metavar="FILE", help="default: the turbine's ipc tuning file")
    ipc.add_argument("--retuned-output", metavar="FILE", help="default: the turbine's ipc_retuned tuning file, or "
                     "beside -o FILE as FILE_retuned.yaml")
    ipc.add_argument("--retuned-only", action="store_true",
                     help="only derive the retuned 1P controller from the existing --output file")
    ipc.set_defaults(run=_cmd_design_ipc)


_PARSERS = {"coupling": _add_coupling, "linearize": _add_linearize, "design": _add_design}


def add_parsers(commands: argparse._SubParsersAction, names: Sequence[str] = tuple(_PARSERS)) -> None:
    """The subparsers of this group's commands ``names`` (default: all of them), added to hawt's ``commands`` in
    that order."""
    for name in names:
        _PARSERS[name](commands)
