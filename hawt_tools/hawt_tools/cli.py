"""The ``hawt`` command (DESIGN.md §8): thin argument parsing over library functions.

Exit codes: 0 success, 1 runtime failure, 2 bad usage or bad input, always with a
one-line message naming the file, field or parameter at fault.
"""
import argparse
import difflib
import json
import math
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, NoReturn, Optional

import yaml

from hawt_bag.errors import BagError

from hawt_tools.graph_file import (GraphError, find_graph, graph_summary, installed_graphs, launch_arguments,
                                   load_graph, package_prefix, yaml_value)
from hawt_tools.view import ViewOptionError
from hawt_core.scheduling import PRIORITY_VARIABLE, SchedulingError, check_priority, set_priority

__all__ = ["main"]


def _cmd_launch(args: argparse.Namespace) -> int:
    graph = load_graph(find_graph(args.graph), launch_arguments(args.arguments), package_prefix)
    view = _view_command(args.view_port, args.view_allow_parameter_sets) if args.view else None
    return _run_graph(graph, args.param, args.mode, args.duration, args.composed, args.record, args.priority, view,
                      args.record_optional)


def _cmd_graph_show(args: argparse.Namespace) -> int:
    """A graph's launch arguments with their defaults, its nodes with their parameter files, and its programs."""
    from hawt_tools.graph_file import ParameterFile, declared_arguments
    from hawt_tools.node_parameters import node_parameter_sources

    path = find_graph(args.graph)
    graph = load_graph(path, launch_arguments(args.arguments), package_prefix)
    declared = declared_arguments(path)
    print(graph.path)
    print("arguments (NAME:=VALUE, default, description):" if declared else "arguments: none")
    defaults = {a.name: "(none)" if a.default is None else a.default or '""' for a in declared}
    name_width = max(map(len, defaults), default=0)
    default_width = max(map(len, defaults.values()), default=0)
    for argument in declared:
        print(f"  {argument.name:<{name_width}}  {defaults[argument.name]:<{default_width}}  "
              f"{argument.description}".rstrip())
    print("nodes (namespace/name, package/executable, then parameters in the order they apply; a value a later "
          "source replaces says what applies):")
    label_width = max(len(node.label) for node in graph.nodes)
    for node in graph.nodes:
        print(f"  {node.label:<{label_width}}  {node.package}/{node.executable}")
        applied = node_parameter_sources(node)
        for source in node.parameters:
            lines = [f"from {source.path}"] if isinstance(source, ParameterFile) else (
                f"{name}: {json.dumps(value)}" + _replaced(value, *applied[name]) for name, value in source.values)
            print("".join(f"    {line}\n" for line in lines), end="")
    if graph.programs:
        print("programs (executable actions, run by hawt launch only):")
    for program in graph.programs:
        print(f"  {program.name}: {' '.join(program.command)}")
    return 0


def _replaced(value: Any, applied: Any, origin: Any) -> str:
    """What ``hawt graph show`` adds to a graph's inline value that a later source replaces: the value that applies
    and where it comes from (a parameter file, or a later inline group)."""
    if applied == value:
        return ""
    return f"  (applies: {json.dumps(applied)}, from {origin.path or 'a later value in the graph'})"


def _run_graph(graph, parameters: List[str], mode: Optional[str], duration: Optional[float], composed: bool,
               record: Optional[str], priority: int = 0, view: Optional[List[str]] = None,
               record_optional: bool = False) -> int:
    """Run a checked graph (separate processes or composed), recording it into ``record`` if given.

    ``priority`` > 0 runs the nodes (not the recorder) under SCHED_FIFO at that priority. With ``view`` (the
    ``view`` executable's command line, :func:`_view_command`) it serves the graph to Foxglove while it runs. A
    recorder that dies is respawned and the plant waits for it (hawt_tools.recording), unless ``record_optional``.
    """
    from hawt_bag.writer import new_bag_path
    from hawt_tools.launcher import ProcessGraph, class_role, launcher_parameters, run_composed
    from hawt_tools.node_parameters import parse_overrides
    from hawt_tools.parameter_check import check_against_plant, check_graph_parameters, takes_parameter
    from hawt_tools.recording import SupervisedRecorder, stop_process

    # --mode beats the graph's own 'mode' values (an override of every node that has one); -p beats --mode
    modes = [f"{spec.label}.mode:={mode}" for spec in graph.nodes if takes_parameter(graph, spec, "mode", class_role)] \
        if mode else []
    overrides = parse_overrides(graph, modes + list(parameters))
    global_parameters = launcher_parameters(graph, bool(record), record_optional)
    check_against_plant(graph, check_graph_parameters(graph, overrides, global_parameters, class_role))  # before start
    if priority:
        check_priority(priority)
    recorder = SupervisedRecorder(new_bag_path(record, "--record"), record_optional) if record else None
    events = viewer = None
    try:
        if view is not None:
            viewer = subprocess.Popen(view, stdin=subprocess.DEVNULL, start_new_session=True)
        if recorder is not None:  # deaths, respawns and stops from outside into the bag
            from hawt_tools.launch_events import LaunchEvents

            namespaces = [spec.full_namespace for spec in graph.nodes]
            events = LaunchEvents(namespaces)
            recorder.watch(events, namespaces)
        if composed:
            if priority:
                set_priority(priority)
            code = run_composed(graph, overrides, duration, global_parameters, events)
        else:
            environment = {PRIORITY_VARIABLE: str(priority)} if priority else {}
            code = ProcessGraph(graph, overrides, global_parameters, environment=environment,
                                events=events).run(duration)
    finally:
        if recorder is not None:
            recorded = recorder.stop()
        if events is not None:
            events.close()
        if viewer is not None:
            stop_process(viewer)
    if recorder is not None and recorded != 0:
        raise RuntimeError(recorder.lost or f"the recorder of {record} failed (exit code {recorded})")
    return code


def _cmd_run(args: argparse.Namespace) -> int:
    from hawt_bag.writer import new_bag_path
    from hawt_tools.in_process import run_graph
    from hawt_tools.node_parameters import parse_overrides
    from hawt_tools.parameter_check import check_against_plant, check_graph_parameters

    graph = load_graph(find_graph(args.graph), launch_arguments(args.arguments), package_prefix)
    overrides = parse_overrides(graph, args.param)
    check_against_plant(graph, check_graph_parameters(graph, overrides))
    record = new_bag_path(args.record, "--record") if args.record else None
    run = run_graph(graph, overrides, record, args.duration, _progress)
    for event in run.events:
        if event["level"] >= 30:
            print(f"{event['kind']} at t={event['step'] * run.description.dt:.2f} s: {event['detail']}",
                  file=sys.stderr)
    print(run.events[-1]["detail"] + (f"; recorded into {args.record}" if args.record else ""))
    return 0


def _cmd_bridge(args: argparse.Namespace) -> int:
    from hawt_tools.discon_bridge import BridgeClosed, BridgeError, run_bridge

    def say(line: str) -> None:
        print(f"hawt bridge: {line}", file=sys.stderr, flush=True)

    try:
        result = run_bridge(Path(args.file), args.graph, args.arguments, args.param, args.record, say, _progress)
    except BridgeError as error:
        raise GraphError(str(error)) from None
    except BridgeClosed as error:
        raise RuntimeError(str(error)) from None
    print(result.events[-1]["detail"] + (f"; recorded into {result.record}" if result.record else ""))
    return 0


def _view_command(port: int, allow_parameter_sets: bool = False) -> List[str]:
    """The command line of hawt_tools' ``view`` executable serving on ``port`` (letting clients set parameters if
    asked)."""

    executable = Path(package_prefix("hawt_tools") or "") / "lib" / "hawt_tools" / "view"
    if not executable.is_file():
        raise RuntimeError("hawt_tools' view executable is not installed (run scripts/setup.sh)")
    return [str(executable), "--port", str(port), *(["--allow-parameter-sets"] if allow_parameter_sets else [])]


def _cmd_view(args: argparse.Namespace) -> int:
    from hawt_tools.view import options_from
    from hawt_tools.view_node import view

    return view(options_from(args))


def _cmd_record(args: argparse.Namespace) -> int:
    from hawt_bag.record_options import options_from
    from hawt_bag.recorder import record

    return record(options_from(args))


def _cmd_replay(args: argparse.Namespace) -> int:
    from hawt_bag.replayer import ReplayOptions, parse_remaps, replay

    options = ReplayOptions(rate=args.rate, loop=args.loop, start_offset=args.start, topics=tuple(args.topics),
                            clock_hz=args.clock, remaps=parse_remaps(args.remap), start_paused=args.start_paused,
                            wait_for_subscribers=args.wait_for_subscribers, wait_timeout=args.wait_timeout,
                            step_trigger=args.step_trigger, step_timeout=args.step_timeout)
    result = replay(args.bag, options,
                    warn=lambda text: print(f"hawt replay: warning: {text}", file=sys.stderr, flush=True))
    print(f"replayed {result.published} messages" + (f" in {result.steps} steps" if args.step_trigger else ""))
    return 0


def _cmd_bag_info(args: argparse.Namespace) -> int:
    from hawt_bag.reader import BagReader

    with BagReader(args.bag) as reader:
        print(reader.info().text())
    return 0


def _cmd_bag_verify(args: argparse.Namespace) -> int:
    from hawt_bag.verification import verify_bag

    report = verify_bag(args.bag)
    print(json.dumps(report.as_dict()) if args.json else report.text())
    return 0 if report.ok else 1


def _cmd_bag_recover(args: argparse.Namespace) -> int:
    from hawt_bag.writer import new_bag_path
    from hawt_bag.recover import recover_bag

    print(recover_bag(args.bag, new_bag_path(args.output, "-o") if args.output else None).text())
    return 0


def _output_path(path: str | Path, option: str, folder: bool = False) -> Path:
    """``path`` as the file (or, with ``folder``, the folder) a command writes once its work is done, checked before
    the work: nothing of the other kind is there, and the folder it goes into exists (GraphError, one line)."""
    target = Path(path)
    if target.exists() and target.is_dir() != folder:
        raise GraphError(f"{option} {path}: " + ("is a file; expected a folder (or a name that does not exist yet)"
                                                 if folder else "is a folder; expected a file name"))
    if not target.resolve().parent.is_dir():
        raise GraphError(f"{option} {path}: the folder {target.resolve().parent} does not exist")
    return target


SCHEDULER_ADDRESS = re.compile(r"(tcp|tls)://[A-Za-z0-9_.\-\[\]:]+:(\d{1,5})")
"""A Dask scheduler's address as ``--scheduler`` takes it: ``tcp://HOST:PORT`` (or ``tls://``)."""


def _scheduler_address(address: Optional[str]) -> Optional[str]:
    """``--scheduler``'s address, checked before anything starts (GraphError, one line)."""
    if address is None:
        return None
    found = SCHEDULER_ADDRESS.fullmatch(address)
    if found is None or not 0 < int(found.group(2)) < 65536:
        raise GraphError(f"--scheduler {address}: expected tcp://HOST:PORT with a port of 1 to 65535 (the address "
                         "dask-scheduler prints)")
    return address


def _progress(line: str) -> None:
    """Stage lines of long work, on an interactive terminal only (stderr stays one error line otherwise)."""
    if sys.stderr.isatty():
        print(f"hawt: {line}", file=sys.stderr, flush=True)


def _warn(command: str, warnings: List[str]) -> None:
    """Each warning of an analysis as one line on stderr."""
    for warning in warnings:
        print(f"hawt {command}: warning: {warning}", file=sys.stderr)


def _report_folder(report: Optional[str]) -> None:
    """``--report DIR`` checked before the analysis: not a file (its missing folders are made when it is written)."""
    if report and Path(report).exists():
        _output_path(report, "--report", folder=True)


def _cmd_analyze(args: argparse.Namespace) -> int:
    from hawt_analysis.analysis_report import analysis_text, write_analysis_report
    from hawt_analysis.run_analysis import analyze_bag

    _report_folder(args.report)
    analysis = analyze_bag(args.bag, args.namespace, progress=_progress)
    _warn("analyze", analysis.summary["warnings"])
    print(json.dumps(analysis.summary) if args.json else analysis_text(analysis.summary))
    if args.report:
        _progress(f"writing the report into {args.report}")
        _progress(f"report: {write_analysis_report(analysis, args.report)}")
    return 0


def _cmd_compare(args: argparse.Namespace) -> int:
    from hawt_analysis.analysis_report import comparison_text, write_comparison_report
    from hawt_analysis.run_analysis import compare_bags

    folders = [Path(path).is_dir() for path in args.bags]
    if any(folders):
        return _compare_campaigns(args, all(folders))
    _report_folder(args.report)
    from hawt_plant.safety_system import TRIP_EVENTS

    analyses, comparison = compare_bags(args.bags, args.namespace, progress=_progress)
    for path, analysis in zip(args.bags, analyses):
        _warn("compare", analysis.summary["warnings"])
        _warn("compare", [f"{path}: {event['kind']} at t={event['time']:.2f} s: from then on its loads are a "
                          f"feathered turbine's" for event in analysis.summary["events"] if event["kind"] in TRIP_EVENTS])
    _warn("compare", comparison["warnings"])
    print(json.dumps(comparison) if args.json else comparison_text(comparison))
    if args.report:
        _progress(f"report: {write_comparison_report(comparison, args.report, analyses)}")
    return 0


def _compare_campaigns(args: argparse.Namespace, only_folders: bool) -> int:
    """Lifetime DELs and AEP, and design loads, of campaign folders' controllers side by side, changes against the
    first. A folder of several DLCs has design loads only (its DLCs' folders have their lifetime tables)."""
    from hawt_analysis.campaign_report import lifetime_text, ultimate_text
    from hawt_tools.campaign import read_lifetime, read_ultimate
    from hawt_tools.campaign_file import CampaignError

    if not only_folders:
        raise GraphError("give bags or campaign folders, not both")
    if args.report:
        raise GraphError("--report: each campaign folder has its report.html already")
    several = len(args.bags) > 1
    lifetime, ultimate = [], []
    for path in map(Path, args.bags):
        prefix = f"{path.name}/" if several else ""
        designs = read_ultimate(path, prefix)
        try:
            lifetime += read_lifetime(path, prefix)
        except CampaignError:
            if not designs:
                raise
        ultimate += designs
    if args.json:
        print(json.dumps({"lifetime": lifetime, "ultimate": ultimate}))
        return 0
    print("\n".join(text for text in (lifetime_text(lifetime) if lifetime else "", ultimate_text(ultimate)) if text))
    return 0


def _cmd_list(args: argparse.Namespace) -> int:
    from hawt_tools.controller_client import ControllerManagerError, manager_namespace
    from hawt_tools.graph_info import controllers_in, controllers_text, snapshot

    if args.namespace is not None:
        manager = manager_namespace(args.namespace)
        try:
            print("\n".join(controllers_text(manager + "/", controllers_in(manager))))
        except ControllerManagerError as error:
            raise RuntimeError(str(error)) from None
        return 0
    found = snapshot(settle=args.settle)
    if found.nodes:
        print(found.text())
        return 0
    print(f"no running graph found (ROS_DOMAIN_ID={os.environ.get('ROS_DOMAIN_ID', '0')}); the graphs that can be "
          "started (hawt graph list, hawt graph show GRAPH):\n  " + ", ".join(installed_graphs()))
    return 0


def _cmd_graph_list(args: argparse.Namespace) -> int:
    """The installed graph files, each with what its leading comment says it is; starts and discovers nothing."""
    graphs = installed_graphs()
    width = max(map(len, graphs), default=0)
    for name, path in graphs.items():
        print(f"{name:<{width}}  {graph_summary(path)}")
    return 0


def _cmd_switch(args: argparse.Namespace) -> int:
    from hawt_tools.controller_client import ControllerManagerError, switch_controllers

    if not args.activate and not args.deactivate:
        raise GraphError("nothing to switch: give --activate NAME and/or --deactivate NAME")
    try:
        result = switch_controllers(args.activate, args.deactivate, strict=not args.best_effort,
                                    ramp_time=-1.0 if args.ramp is None else args.ramp, at_step=args.at_step,
                                    namespace=args.namespace)
    except ControllerManagerError as error:
        raise RuntimeError(str(error)) from None
    if not result.ok:
        raise GraphError(f"refused: {result.message}")
    print(f"switched {result.message}")
    return 0


def _cmd_lifecycle(args: argparse.Namespace) -> int:
    from hawt_tools.controller_client import ControllerManagerError, lifecycle_transition

    try:
        ok, state = lifecycle_transition(args.node, args.transition, args.namespace)
    except ControllerManagerError as error:
        raise RuntimeError(str(error)) from None
    if not ok:
        raise GraphError(f"{args.node}: transition {args.transition} refused (state {state}; the node's log "
                         "says why)")
    print(f"{args.node}: {state}")
    return 0


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
    points = coupling_survey(nrel_5mw(), args.wind_speeds, args.harmonics, progress=_progress)
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


def _cmd_linearize(args: argparse.Namespace) -> int:
    """The plant's linear models in the Coleman frame per wind speed, the modes table and the Campbell diagram."""
    from hawt_controllers.laws.coleman_models import save_models
    from hawt_controllers.design.linear_models import (band_offset, campbell_figure, decoupling_offset, labelled_modes, linearize_power_curve, tilt_yaw_response)

    for v in args.wind_speeds:
        if not 3.0 <= v <= 30.0:
            raise GraphError(f"--wind-speeds: {v:g} m/s is outside the plant's 3..30 m/s")
    if not 1 <= args.azimuths <= 360:
        raise GraphError(f"--azimuths: {args.azimuths} is outside 1..360")
    if not 0.0 <= args.settle <= 3600.0:
        raise GraphError(f"--settle: {args.settle:g} s is outside 0..3600 s")
    plant = _plant_overrides(args.arguments)
    inflow = plant.get("dynamic_inflow")
    if inflow == "turbine":  # the turbine's own option, which the linear models cannot take either when it is on
        from hawt_plant.turbine import turbine_from

        inflow = turbine_from(str(plant.get("turbine_file") or "nrel_5mw")).aerodynamics.dynamic_inflow
    if inflow is True:
        raise GraphError("dynamic_inflow:=true: the linear models have quasi-steady aerodynamics (no inflow states "
                         "yet); linearise without it")
    output = _output_path(args.output, "--output")
    _progress(f"linearizing at {len(args.wind_speeds)} wind speed(s), {args.azimuths} azimuths each, "
              f"{args.workers} worker(s)")
    start = time.monotonic()

    def done(model, count: int, total: int) -> None:
        _progress(f"{model.wind_speed:g} m/s done in {model.seconds:.1f} s ({count}/{total})")

    models = linearize_power_curve(args.wind_speeds, args.azimuths, args.settle, plant, args.workers, done)
    save_models(output, models)
    print(f"{len(models)} models ({models[0].loops}; states, inputs and outputs in the Coleman frame, averaged over "
          f"{args.azimuths} azimuths) written to {output} in {time.monotonic() - start:.1f} s")
    print("per wind speed: rotor speed, pitch, dM_cos/dtheta_cos at DC, Disario's 1P offsets: decoupling at DC from "
          "the pitch command (the IPC design's) and from the pitch angle, and minimising the mean |P12| over "
          "0.1-1 rad/s from the angle (Disario: 19 deg at 25 m/s for FAST's NREL 5 MW); then each oscillating "
          "mode: its dominant state, frequency [Hz]/damping ratio")
    for model in models:
        modes = "  ".join(f"{m.state} {m.frequency:.3f}/{m.damping:.3f}" for m in labelled_modes(model.model))
        gain = tilt_yaw_response(model.model, [0.0])[0, 0, 0].real
        offsets = [math.degrees(decoupling_offset(model.model, "command")),
                   math.degrees(decoupling_offset(model.model, "angle")), math.degrees(band_offset(model.model))]
        print(f"{model.wind_speed:5.1f} m/s  {model.rotor_speed * 30 / math.pi:5.2f} rpm  pitch "
              f"{math.degrees(model.pitch):5.2f} deg  {gain / 1e6:7.2f} MN*m/rad  offsets {offsets[0]:4.1f} "
              f"{offsets[1]:4.1f} {offsets[2]:4.1f} deg  {modes}")
    if args.plot:
        campbell_figure(models, Path(args.plot))
        print(f"Campbell diagram: {args.plot}")
    return 0


def _cmd_design_lqg(args: argparse.Namespace) -> int:
    """Selvam's FB-FF IPC designed on the plant's linear model at one wind speed: checks and closed-loop shape."""
    import numpy as np

    from hawt_core.exceptions import ConfigurationError
    from hawt_controllers.design.ipc_design import DEFAULT_FILE
    from hawt_controllers.laws.coleman_models import load_models
    from hawt_controllers.plugins.lqg_ipc import DEFAULT_MODELS
    from hawt_controllers.laws.lqg_design import LqgWeights, controllability_rank, design_lqg, observability_rank
    from hawt_controllers.laws.lqg_ipc import closed_loop_response, frequency_response_figure

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
        design = design_lqg(model.model, args.dt, weights)
    except ConfigurationError as error:
        raise GraphError(str(error)) from None
    n = design.states
    print(f"LQG FB-FF IPC (Selvam 2009) at {args.wind_speed:g} m/s from {path}, dt {args.dt:g} s, loops "
          f"{model.loops}; weights {weights}")
    print(f"observability of the augmented model (with the wind states): rank "
          f"{observability_rank(design.a_est, design.c_est)} of {n + 2}; controllability of the turbine states: "
          f"rank {controllability_rank(design.plant.a, design.plant.b_theta)} of {n}")
    radius = float(np.max(np.abs(np.linalg.eigvals(design.inverse[0]))))
    print(f"SDMI inverse: spectral radius {radius:.6f} (stable below 1)")
    ipc_h1 = yaml.safe_load(DEFAULT_FILE.read_text())["/**/ipc_h1"]["ros__parameters"]
    gains = (ipc_h1["integral_gain"], ipc_h1["phase_offset"])
    one_p = model.rotor_speed
    frequencies = {"0.01 rad/s": 0.01, "1P": one_p, "2P": 2 * one_p, "3P": 3 * one_p}
    print("closed loop |u_cos -> M_cos| / |u_sin -> M_sin| [MN*m per m/s]:")
    print(f"{'':16s}" + "".join(f"{name:>20s}" for name in frequencies))
    for label, kind in (("no IPC", "none"), ("integrator IPC", "integrator"), ("FB-FF (LQG)", "lqg")):
        response = np.abs(closed_loop_response(design, list(frequencies.values()), kind, *gains))
        print(f"{label:16s}" + "".join(f"{response[k, 0, 0]:10.3f}/{response[k, 1, 1]:<9.3f}"
                                         for k in range(len(frequencies))))
    if args.plot:
        frequency_response_figure(design, Path(args.plot), one_p, *gains)
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
        _output_path(args.output, "-o")
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
            _output_path(path, option)
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


def _plant_overrides(words: List[str]) -> Dict[str, object]:
    """NAME:=VALUE words as the plant's parameters, each checked against the plant node's table."""
    from hawt_core.parameter_table import ParameterError
    from hawt_plant.plant_setup import PARAMETERS

    table = {spec.name: spec for spec in PARAMETERS}
    values = {}
    for name, text in launch_arguments(words).items():
        if name not in table:
            close = difflib.get_close_matches(name, table, n=1)
            raise GraphError(f"plant parameter {name!r} does not exist" + (f" (did you mean {close[0]!r}?)"
                                                                            if close else ""))
        try:
            values[name] = table[name].typed(yaml_value(text))  # 8e-11 a float, as everywhere else
        except ParameterError as error:
            raise GraphError(f"plant parameter {error}") from None
    return values


def _coupling_identified(args: argparse.Namespace) -> int:
    """``hawt coupling --bag``: the tilt/yaw plant identified from a recorded excitation run."""
    from hawt_analysis.identification import identify_coleman_plant

    _progress(f"identifying the Coleman-frame plant of harmonic {args.harmonics[0]} from {args.bag}")
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


def _cmd_transfer(args: argparse.Namespace) -> int:
    """Zalkind & Pao's load-transfer model fitted over recorded steady runs, per link and region."""
    from hawt_analysis.two_bladed import transfer_model_from_bags

    if len(args.bags) < 2:
        raise GraphError("give two or more bags (steady runs at different wind speeds) to fit over")
    try:
        _, fits = transfer_model_from_bags([Path(path) for path in args.bags], fine_pitch=args.fine_pitch)
    except ValueError as error:
        raise GraphError(str(error)) from None
    rows = [{"input": source, "output": target, "region": region, "gain": [fit.gain.real, fit.gain.imag],
             "offset": [fit.offset.real, fit.offset.imag], "residual_rms": fit.residual_rms, "points": fit.points}
            for (source, target), by_region in fits.items() for region, fit in sorted(by_region.items())]
    if args.json:
        print(json.dumps(rows))
        return 0
    print(f"{'input':>14s} -> {'output':<14s} region  |gain|  arg(gain) [deg]  |offset| [MN*m]  "
          "residual [MN*m]  points")
    for row in rows:
        gain, offset = complex(*row["gain"]), complex(*row["offset"])
        print(f"{row['input']:>14s} -> {row['output']:<14s} {row['region']:>6d}  {abs(gain):6.3f}  "
              f"{math.degrees(math.atan2(gain.imag, gain.real)):15.1f}  {abs(offset) / 1e6:15.3f}  "
              f"{row['residual_rms'] / 1e6:15.3f}  {row['points']:6d}")
    return 0


def _cmd_validate(args: argparse.Namespace) -> int:
    """The turbine's cases in OpenFAST and in hawt with ROSCO on both, and the report of their differences."""
    from hawt_plant.turbine import TurbineDefinitionError, turbine_from
    from hawt_tools.openfast_case import OpenFastFailed, deck_of, openfast_executable
    from hawt_tools.validation import DEFAULT_CASES, parse_case, run_case, with_duration, write_report

    try:
        openfast = openfast_executable(args.openfast)
        cases = [parse_case(text, args.duration) for text in args.case] if args.case else \
            [with_duration(case, args.duration) if args.duration is not None else case for case in DEFAULT_CASES]
        turbine_from(args.turbine)
        deck = deck_of(args.turbine)
    except (ValueError, TurbineDefinitionError) as error:
        raise GraphError(str(error)) from None
    out = Path(args.output or f"validation-{Path(args.turbine).name}")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise GraphError(f"-o {out}: cannot create the report folder ({error.strerror})") from None
    graph = find_graph("validation")
    print(f"hawt validate {args.turbine}: {len(cases)} case(s) in OpenFAST ({openfast}) and in hawt, deck {deck}, "
          f"report in {out}", flush=True)
    results = []
    for number, case in enumerate(cases, start=1):
        print(f"case {number} of {len(cases)}: {case.name}, {case.duration:g} s simulated", flush=True)
        try:
            result = run_case(case, args.turbine, graph, deck, openfast, out, args.param,
                              lambda line: print(line, flush=True))
        except OpenFastFailed as error:
            raise RuntimeError(str(error)) from None
        results.append(result)
        outside = [row["label"] for row in result.rows if not row["within"]]
        print(f"  {case.name}: {len(result.rows) - len(outside)} of {len(result.rows)} figures within tolerance"
              + (f"; outside: {', '.join(outside)}" if outside else ""), flush=True)
    page = write_report(args.turbine, openfast, results, out)
    print(f"report: {out / 'validation.md'} and {page}")
    return 0


def _cmd_turbine_import(args: argparse.Namespace) -> int:
    """An OpenFAST deck converted into DIR/turbine.yaml and DIR/airfoils/, checked by loading it."""
    from hawt_plant.turbine import TurbineDefinitionError, load_turbine
    from hawt_tools.turbine_import import DeckError, import_deck, write_turbine

    from hawt_tools.openfast_case import DeckNotFound, keep_deck

    try:
        imported = import_deck(args.deck)
        path = write_turbine(imported, args.output or Path(args.deck).stem)
        load_turbine(path)
        deck = keep_deck(Path(args.deck), path.parent)
    except (DeckError, TurbineDefinitionError, DeckNotFound) as error:
        raise GraphError(str(error)) from None
    print(f"{args.deck} -> {path} and {len(imported.airfoils)} airfoil polars in {path.parent / 'airfoils'}; each "
          "value names its source file and key")
    for title, lines in (("approximated", imported.approximations), ("not modelled", imported.not_modelled)):
        print(f"{title}:" + "".join(f"\n  - {line}" for line in lines))
    print(f"the deck, for hawt validate: {deck}")
    print(f"next: hawt turbine show {path.parent}; hawt design cpc --turbine {path.parent} (writes its cpc.yaml); "
          f"then hawt launch baseline turbine:={path.parent}")
    return 0


def _cmd_turbine_show(args: argparse.Namespace) -> int:
    """Rated values, the plant's Cp-max and optimal tip-speed ratio, and first modes of a turbine definition."""
    from hawt_plant.turbine import TurbineDefinitionError, turbine_from
    from hawt_plant.turbine_summary import format_summary, turbine_summary

    try:
        turbine = turbine_from(args.turbine)
    except TurbineDefinitionError as error:
        raise GraphError(str(error)) from None
    print(format_summary(turbine_summary(turbine)))
    return 0


def _cmd_campaign(args: argparse.Namespace) -> int:
    """Every case of a campaign file on Dask workers; tables, lifetime loads and a report in the output folder. A
    file of several DLCs runs each into its folder ``dlc-N.N`` and prints the design loads over them all, which
    ``ultimate.csv`` in the output folder keeps."""
    import pandas

    from hawt_analysis.campaign_report import ultimate_text, write_design_load_report
    from hawt_analysis.ultimate import governing_loads
    from hawt_tools.campaign_file import load_campaigns

    if args.workers is not None and args.workers < 1:
        raise GraphError(f"--workers {args.workers}: expected 1 or more")
    scheduler = _scheduler_address(args.scheduler)
    campaigns = load_campaigns(Path(args.campaign))
    output = _output_path(args.output or Path(args.campaign).stem, "-o", folder=True)
    several = len(campaigns) > 1
    tables, failed = [], 0
    for campaign in campaigns:  # a DLC with failed cases leaves the others to run; an interruption stops them all
        if several:
            print(f"DLC {campaign.dlc}:", flush=True)
        status, ultimate = _run_campaign(campaign, output / f"dlc-{campaign.dlc}" if several else output, args,
                                         scheduler)
        if status == 130:
            return status
        failed = failed or status
        tables.append(ultimate)
    if several and any(tables):
        governing = governing_loads(tables)
        over = [campaign.dlc for campaign in campaigns]
        pandas.DataFrame(governing).to_csv(output / "ultimate.csv", index=False)
        print(ultimate_text(governing, over))
        page = write_design_load_report(f"hawt campaign: {campaigns[0].path.name}, design loads", governing, over,
                                        output, [f"dlc-{dlc}/report.html" for dlc in over
                                                 if (output / f"dlc-{dlc}" / "report.html").is_file()])
        print(f"design loads over the DLCs: {output / 'ultimate.csv'}\nreport: {page}")
    return failed


def _run_campaign(campaign, output: Path, args: argparse.Namespace, scheduler: str) -> tuple[int, list]:
    """One DLC's campaign into ``output``: its exit status (0, 130 interrupted, 1 failed cases) and its ultimate
    table."""
    from hawt_analysis.campaign_report import lifetime_text, ultimate_text, write_campaign_report
    from hawt_core.stop_signals import stop_signals
    from hawt_tools.campaign import governing_series, lifetime_table, run_campaign, ultimate_table, write_tables

    # Ctrl-C or SIGTERM stops the campaign, keeping what finished, also in a process started with SIGINT ignored
    # (a script's background job, a test runner's worker)
    with stop_signals(signal.default_int_handler):
        done = run_campaign(campaign, output, args.workers, scheduler, args.bags,
                            report=lambda line: print(line, flush=True))
    ultimate = []
    if done.rows:
        tables = write_tables(campaign, done.rows, output)
        lifetime = lifetime_table(campaign, done.rows)
        print(f"lifetime DEL (Miner, m per channel, site mean {campaign.site.mean:g} m/s, Weibull k "
              f"{campaign.site.shape:g}) and AEP, over the bins run" + (
                  f" (in DLC {campaign.dlc}'s extreme conditions: to compare controllers, not a fatigue estimate):"
                  if campaign.dlc not in ("1.1", "1.2") else ":"))
        print(lifetime_text(lifetime))
        ultimate = ultimate_table(campaign, done.rows)
        governing = []
        if ultimate:
            print(ultimate_text(ultimate))
            cases = {(e["controller"], e.get("wind_speed"), e.get("seed")) for e in ultimate if e["dlc"] != "1.1"}
            if cases and not (done.failed or done.interrupted):
                print(f"running the {len(cases)} governing case(s) again for their time series (report)", flush=True)
                governing = governing_series(campaign, ultimate)
        page = write_campaign_report(f"hawt campaign: {campaign.path.name}", done.rows, lifetime, output, tables,
                                     ultimate, governing)
        print(f"tables: {', '.join(str(path) for path in tables.values())}\nreport: {page}")
    if done.interrupted:
        print(f"hawt campaign: interrupted; {len(done.rows)} finished case(s) kept in {output}: run the same command "
              "again to resume", file=sys.stderr)
        return 130, ultimate
    if done.failed:
        for line in done.failed.values():
            print(f"hawt campaign: failed: {line}", file=sys.stderr)
        return 1, ultimate
    return 0, ultimate


def _cmd_demo(args: argparse.Namespace) -> int:
    """Baseline and IPC (1P+2P) graphs on the same turbulent wind, each recorded; their loads compared. Without a
    ROS_DOMAIN_ID of the user's, on a domain reserved for the demo (domain_coordinator, as the test suite does), so
    another graph on the machine's default domain with the same namespace cannot feed its controllers."""
    from hawt_analysis.analysis_report import headline_text, write_comparison_report
    from hawt_analysis.run_analysis import compare_bags

    if "ROS_DOMAIN_ID" not in os.environ:  # the default domain is every ROS user's on this machine: take one alone
        from domain_coordinator import domain_id

        with domain_id() as domain:
            os.environ.update(ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
            _progress(f"hawt demo: on ROS domain {domain}, reserved for it (another graph on this machine cannot "
                      "reach its topics; set ROS_DOMAIN_ID to choose the domain)")
            try:
                return _cmd_demo(args)
            finally:
                for name in ("ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE"):
                    os.environ.pop(name, None)
    run = time.strftime("demo-%Y%m%d-%H%M%S")
    bags = Path(args.output) / run
    bags.mkdir(parents=True, exist_ok=False)
    wind = {"wind_type": "turbulent", "wind_speed": str(args.wind_speed), "seed": str(args.seed),
            "duration": str(args.duration)}
    paths = []
    # IPC 1P+2P: the project's study shows 3P adds little to the blades and raises the tower loads
    for name, arguments in (("baseline", {}), ("ipc", {"ipc_h3": "false"})):
        path = bags / f"{name}.mcap"
        _progress(f"hawt demo: {name} graph, {args.duration:g} s of IEC class B turbulence at {args.wind_speed:g} m/s "
                  f"(seed {args.seed}), recording {path}")
        graph = load_graph(find_graph(name), {**wind, **arguments}, package_prefix)
        # plant/blade_loads has three subscribers (cpc, mbc, recorder): step 0 waits for all of them
        _run_graph(graph, ["plant.wait_for_subscribers:=3"], None, None, False, str(path))
        paths.append(path)
    analyses, comparison = compare_bags([str(p) for p in paths], None, progress=_progress)
    print(f"hawt demo: IPC 1P+2P against the baseline, {args.duration:g} s of IEC class B turbulence at "
          f"{args.wind_speed:g} m/s (seed {args.seed})")
    print(headline_text(comparison))
    report = write_comparison_report(comparison, bags / "report", analyses)
    print(f"every number (DELs, harmonics, spectra, pitch activity): {report}\n"
          f"(or: ./hawt compare {' '.join(str(p) for p in paths)})")
    return 0


def _within(low: float, high: float = math.inf, above: bool = False, kind: type = float) -> Callable[[str], float]:
    """argparse's ``type=`` of an option that takes a finite number of ``kind`` from ``low`` (or above it) to ``high``.

    Declared with the option, the range holds in every command that has it, and argparse checks it while it reads the
    command line, before any command starts; anything else is its one-line refusal (`_Parser`), exit 2.
    """
    lower = f"above {low:g}" if above else f"from {low:g}"
    span = f"{lower} to {high:g}" if high < math.inf else lower if above else f"of {low:g} or more"
    expected = f"expected a {'whole' if kind is int else 'finite'} number {span}"

    def number(text: str) -> float:
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text}: {expected}") from None
        if not (math.isfinite(value) and (value > low if above else value >= low) and value <= high):
            raise argparse.ArgumentTypeError(f"{text}: {expected}")
        return value

    return number


_POSITIVE = _within(0.0, above=True)
"""Seconds, speed factors, timeouts: above 0 (and finite)."""
_NOT_NEGATIVE = _within(0.0)
_PORT = _within(0, 65535, kind=int)
"""A TCP port as `hawt view` takes it (0: any free one, which the view prints)."""
_PRIORITY = _within(1, 99, kind=int)
"""A SCHED_FIFO priority."""


class _Parser(argparse.ArgumentParser):
    """argparse with the module's one-line refusal of bad usage (exit 2), the usage left to ``--help``."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: {message}\n")


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="hawt", description="ROS 2 toolkit for wind-turbine load alleviation: run node graphs of a "
                                 "simulated turbine and its pitch controllers.")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    launch = commands.add_parser(
        "launch", help="run a node graph (ROS 2 YAML launch format), each node in its own process",
        description="Run a node graph: each node in its own OS process (or all in one with --composed), "
                    "output prefixed with the node name, all stopped cleanly on Ctrl-C/SIGTERM.")
    launch.add_argument("graph", metavar="GRAPH", help="graph file, or the name of an installed graph")
    launch.add_argument("arguments", nargs="*", metavar="NAME:=VALUE", help="launch arguments of the graph")
    launch.add_argument("--duration", type=_POSITIVE, metavar="S",
                        help="stop after S wall-clock seconds (default: run until a node with on_exit: "
                             "shutdown finishes, every node has finished, or Ctrl-C)")
    launch.add_argument("--mode", choices=("lockstep", "realtime"),
                        help="timing mode, given to every node as its 'mode' parameter")
    launch.add_argument("--composed", action="store_true", help="run all nodes in this process on one executor")
    launch.add_argument("--priority", type=_PRIORITY, default=0, metavar="N",
                        help="run the nodes under SCHED_FIFO at priority N (1-99), as a realtime loop should: "
                             "fewer late steps in --mode realtime (needs root or CAP_SYS_NICE; the recorder keeps "
                             "normal scheduling)")
    launch.add_argument("-p", dest="param", action="append", default=[], metavar="NODE.PARAM:=VALUE",
                        help="override a parameter of one node (repeatable)")
    launch.add_argument("--record", metavar="FILE.mcap",
                        help="record every topic into this new bag; the recorder starts before the graph "
                             "and stops after it. A recorder that dies is respawned, and a lockstep plant waits "
                             "for it, so the bag has every step")
    launch.add_argument("--record-optional", action="store_true",
                        help="with --record: a recorder that dies is not respawned and the plant goes on without "
                             "it after its recorder_timeout (the bag then misses steps)")
    launch.add_argument("--view", action="store_true",
                        help="serve the graph live to Foxglove while it runs (as 'hawt view', on --view-port)")
    launch.add_argument("--view-port", type=_PORT, default=8765, metavar="N",
                        help="port of --view (default 8765; 0: any free one)")
    launch.add_argument("--view-allow-parameter-sets", action="store_true",
                        help="let --view's clients set parameters (as 'hawt view --allow-parameter-sets')")
    launch.set_defaults(run=_cmd_launch)

    run = commands.add_parser(
        "run", help="run a graph's cores in this process, without middleware (bit-identical to lockstep)",
        description="The in-process engine: reads the same graph and parameter files as 'launch', builds the "
                    "same plant and controller cores and steps them in lockstep order with no DDS, so the "
                    "result equals 'hawt launch GRAPH' in lockstep bit for bit, only faster. A switch "
                    "schedule in steps works the same way. --record writes the graph's topics to MCAP for "
                    "analyze and compare.")
    run.add_argument("graph", metavar="GRAPH", help="graph file, or the name of an installed graph")
    run.add_argument("arguments", nargs="*", metavar="NAME:=VALUE", help="launch arguments of the graph")
    run.add_argument("--duration", type=_POSITIVE, metavar="S",
                     help="simulated seconds to run (default: the plant's duration parameter)")
    run.add_argument("-p", dest="param", action="append", default=[], metavar="NODE.PARAM:=VALUE",
                     help="override a parameter of one node (repeatable)")
    run.add_argument("--record", metavar="FILE.mcap", help="write the run's topics into this new bag")
    run.set_defaults(run=_cmd_run)

    bridge = commands.add_parser(
        "bridge", help="a graph as the controller of a simulator that calls libhawt_discon.so (OpenFAST's ServoDyn)",
        description="Serve one simulator run: libhawt_discon.so (ros2_ws/lib/, ServoDyn's DLL_FileName) reads "
                    "the bridge file (DLL_InFile) and sends each DISCON call over its socket; the graph steps in "
                    "process with the call's measurements as its plant and answers that step's pitch and torque. "
                    "Ends at the simulator's last call. See hawt_tools/discon_bridge.py for the file.")
    bridge.add_argument("graph", nargs="?", metavar="GRAPH", help="graph file or installed graph (default: the "
                        "bridge file's graph)")
    bridge.add_argument("arguments", nargs="*", metavar="NAME:=VALUE", help="launch arguments of the graph")
    bridge.add_argument("--file", required=True, metavar="BRIDGE_FILE",
                        help="the bridge file the simulator is given (its socket, timeouts, graph)")
    bridge.add_argument("-p", dest="param", action="append", default=[], metavar="NODE.PARAM:=VALUE",
                        help="override a parameter of one node (repeatable)")
    bridge.add_argument("--record", metavar="FILE.mcap", help="write the run's topics into this new bag")
    bridge.set_defaults(run=_cmd_bridge)

    from hawt_bag.record_options import add_record_arguments

    record = commands.add_parser("record", help="record topics of the running graph into an MCAP bag",
                                 description="Record all topics (or the chosen ones) into a new MCAP bag until "
                                             "Ctrl-C/SIGTERM; topics that appear later are picked up.")
    add_record_arguments(record)
    record.set_defaults(run=_cmd_record)

    from hawt_tools.view import add_view_arguments

    view = commands.add_parser(
        "view", help="serve the running graph live to Foxglove (WebSocket; topics, plant time, parameters)",
        description="Serve every topic of the running graph on a Foxglove WebSocket (ROS 2 channels: ros2msg "
                    "schemas, CDR messages as published), timed by the plant's clock, with the nodes' "
                    "parameters to view and set. In Foxglove: Open connection, Foxglove WebSocket, "
                    "ws://localhost:8765; layout: hawt_tools/foxglove/hawt_layout.json.")
    add_view_arguments(view)
    view.set_defaults(run=_cmd_view)

    replay = commands.add_parser("replay", help="publish a bag's messages again, timed or step by step",
                                 description="Replay a bag at its recorded timing (times --rate), or step by step "
                                             "through a graph with --step-trigger. Live control: parameters "
                                             "'paused' and 'rate' of node hawt_player, topic "
                                             "/hawt_player/play_next (std_msgs/Empty) while paused.")
    replay.add_argument("bag", metavar="FILE.mcap")
    replay.add_argument("-r", "--rate", type=_POSITIVE, default=1.0, metavar="R", help="speed factor (default 1)")
    replay.add_argument("-l", "--loop", action="store_true", help="start again at the end")
    replay.add_argument("--start", type=_NOT_NEGATIVE, default=0.0, metavar="S",
                        help="start S seconds after the bag's first message")
    replay.add_argument("--topics", nargs="+", default=[], metavar="T", help="publish only these topics")
    replay.add_argument("--clock", type=_NOT_NEGATIVE, nargs="?", const=40.0, default=0.0, metavar="HZ",
                        help="publish /clock at HZ (default 40 when given without a value); in step replay, "
                             "once per step")
    replay.add_argument("--remap", "-m", nargs="+", default=[], metavar="FROM:=TO", help="publish a topic under "
                                                                                         "another name")
    replay.add_argument("-p", "--start-paused", action="store_true", help="start paused")
    replay.add_argument("--wait-for-subscribers", action="store_true",
                        help="start only once every topic has a subscriber")
    replay.add_argument("--wait-timeout", type=_POSITIVE, default=10.0, metavar="S",
                        help="how long to wait for subscribers and the trigger's publisher (default 10)")
    replay.add_argument("--step-trigger", metavar="TOPIC",
                        help="step replay: after publishing the messages of step k, wait for step k on TOPIC "
                             "(e.g. /wt1/control/pitch_command)")
    replay.add_argument("--step-timeout", type=_POSITIVE, default=10.0, metavar="S",
                        help="step replay: how long to wait for each step's answer (default 10)")
    replay.set_defaults(run=_cmd_replay)

    bag = commands.add_parser("bag", help="inspect, verify or rescue a bag (info, verify, recover)")
    bag_commands = bag.add_subparsers(dest="bag_command", required=True, metavar="SUBCOMMAND")
    info = bag_commands.add_parser("info", help="duration, size, compression, topics with type, QoS and count")
    info.add_argument("bag", metavar="FILE.mcap")
    info.set_defaults(run=_cmd_bag_info)
    verify = bag_commands.add_parser(
        "verify", help="check every stepped topic for missing and repeated steps, and the file for its summary",
        description="Check a recording lost nothing: plant/blade_loads, plant/state and control/pitch_command must "
                    "hold every step from their first to their last; other stepped topics are listed with their "
                    "runs of steps; a step recorded twice is an error unless resent identical; the file must have "
                    "its summary. Exit 0 if all is well, 1 if not, 2 if the file is missing or not MCAP.")
    verify.add_argument("bag", metavar="FILE.mcap")
    verify.add_argument("--json", action="store_true", help="print the same facts as one JSON object")
    verify.set_defaults(run=_cmd_bag_verify)
    recover = bag_commands.add_parser("recover", help="rewrite what an unfinished bag holds into a complete one")
    recover.add_argument("bag", metavar="FILE.mcap")
    recover.add_argument("-o", "--output", metavar="OUT.mcap", help="default: FILE.recovered.mcap")
    recover.set_defaults(run=_cmd_bag_recover)

    graph = commands.add_parser("graph", help="the installed graph files (list) and what one declares (show)")
    graph_commands = graph.add_subparsers(dest="graph_action", required=True, metavar="ACTION")
    graph_list = graph_commands.add_parser(
        "list", help="the installed graph files, each with what it is (offline: nothing runs)",
        description="List the graphs installed with hawt's packages by name, each with the first sentence of its "
                    "file's comment. Starts and discovers nothing; hawt list shows a running graph.")
    graph_list.set_defaults(run=_cmd_graph_list)
    graph_show = graph_commands.add_parser(
        "show", help="a graph's launch arguments with defaults, its nodes and parameter files, its programs",
        description="List a graph file's launch arguments (NAME:=VALUE) with their defaults and descriptions, "
                    "then its nodes (namespace/name, package/executable) with their parameter files as the "
                    "defaults (or the given arguments) resolve them, then its executable programs. Starts nothing.")
    graph_show.add_argument("graph", metavar="GRAPH", help="graph file, or the name of an installed graph")
    graph_show.add_argument("arguments", nargs="*", metavar="NAME:=VALUE",
                            help="launch arguments to resolve the parameter files with")
    graph_show.set_defaults(run=_cmd_graph_show)

    analyze = commands.add_parser("analyze", help="DELs, harmonics, spectra, pitch activity and events of a run",
                                  description="Analyse one turbine's run in a bag: plant/blade_loads and "
                                              "plant/state (required), control/pitch_command and control/events.")
    analyze.add_argument("bag", metavar="FILE.mcap")
    analyze.add_argument("--json", action="store_true", help="print the JSON object of DESIGN §8")
    analyze.add_argument("--report", metavar="DIR", help="write index.html, plots and summary.json into DIR")
    analyze.add_argument("--namespace", metavar="NS", help="the turbine (e.g. /wt1) when the bag holds several")
    analyze.set_defaults(run=_cmd_analyze)

    compare = commands.add_parser("compare", help="several runs (or campaign folders) side by side, changes "
                                                  "against the first")
    compare.add_argument("bags", nargs="+", metavar="FILE.mcap|CAMPAIGN_DIR",
                         help="bags, or the output folders of hawt campaign (their lifetime DELs and AEP, and "
                              "their design loads where they have ultimate.csv)")
    compare.add_argument("--json", action="store_true", help="print the comparison as JSON (campaign folders: "
                                                             "{\"lifetime\": […], \"ultimate\": […]})")
    compare.add_argument("--report", metavar="DIR", help="write index.html, plots and comparison.json into DIR")
    compare.add_argument("--namespace", metavar="NS", help="the turbine (e.g. /wt1) when a bag holds several")
    compare.set_defaults(run=_cmd_compare)

    listing = commands.add_parser("list", help="the nodes, topics (with types) and controllers (with states) of the "
                                               "running graph")
    listing.add_argument("--settle", type=float, default=1.0, metavar="S",
                         help="discovery: wait until the node list is unchanged for S seconds")
    listing.add_argument("--namespace", metavar="NS", help="only the controllers of the turbine NS (e.g. /wt1), "
                                                           "asked of its controller_manager without discovering the "
                                                           "rest of the graph first")
    listing.set_defaults(run=_cmd_list)

    switch = commands.add_parser(
        "switch", help="activate and deactivate controllers of a running graph at one plant step",
        description="Ask the graph's controller_manager to switch controllers atomically at one plant step "
                    "(ros2_control semantics; one active claimant per command interface). An outgoing "
                    "contribution ramps out over the ramp time, an incoming one ramps in; a controller that replaces "
                    "another on its interfaces starts from the other's output. Prints the step the switch takes effect "
                    "at.")
    switch.add_argument("--activate", nargs="+", default=[], metavar="NAME", help="controllers to activate")
    switch.add_argument("--deactivate", nargs="+", default=[], metavar="NAME", help="controllers to deactivate")
    switch.add_argument("--ramp", type=float, metavar="S", help="ramp time (default: the manager's ramp_time)")
    switch.add_argument("--best-effort", action="store_true",
                        help="apply what can be applied (default STRICT: refuse the whole switch if any name fails)")
    switch.add_argument("--at-step", type=int, default=0, metavar="K",
                        help="plant step to switch at (default: as soon as possible)")
    switch.add_argument("--namespace", metavar="NS", help="turbine namespace of the controller manager (needed only "
                                                          "if the graph has several)")
    switch.set_defaults(run=_cmd_switch)

    lifecycle = commands.add_parser(
        "lifecycle", help="a controller's lifecycle state, or a standard transition (as ros2 lifecycle set)",
        description="Print a lifecycle node's state, or ask it for a standard transition first. A controller "
                    "hands activate/deactivate to its controller_manager, so they take effect at a plant step "
                    "exactly as 'hawt switch' does.")
    lifecycle.add_argument("node", metavar="NODE", help="node name (e.g. ipc_h1 or /wt1/ipc_h1)")
    from hawt_controllers.plugins.switching import TRANSITIONS

    lifecycle.add_argument("transition", nargs="?", choices=TRANSITIONS, help="the transition to ask for")
    lifecycle.add_argument("--namespace", metavar="NS", help="the turbine (e.g. /wt1) when several are running")
    lifecycle.set_defaults(run=_cmd_lifecycle)

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
                    "that fit it together (1P first, up to 85 %), and write the ipc graph's parameter file "
                    "(the turbine's ipc tuning) with the others inactive, and the switching graph's retuned 1P "
                    "controller derived from it.")
    ipc.add_argument("--turbine", default="nrel_5mw", metavar="T",
                     help="a turbine.yaml, its folder, or a packaged turbine's name (default nrel_5mw); a folder's "
                          "tunings go beside it")
    ipc.add_argument("--harmonics", type=_within(1, kind=int), nargs="+", default=[1, 2, 3], metavar="N",
                     help="the harmonics to design, each its ipc_hN node (default 1 2 3)")
    ipc.add_argument("--wind-speeds", type=_POSITIVE, nargs="+", default=[13.0, 16.0, 18.0, 20.0, 24.0],
                     metavar="V", help="operating points above rated [m/s] (default 13 16 18 20 24)")
    ipc.add_argument("--reference-speed", type=_POSITIVE, default=18.0, metavar="V",
                     help="where the gain is designed [m/s] (default 18)")
    ipc.add_argument("--bandwidth-hz", type=_POSITIVE, default=0.1, metavar="F",
                     help="loop crossover [Hz] (default 0.1, van Engelen's)")
    ipc.add_argument("--loop-delay", type=_NOT_NEGATIVE, default=0.1, metavar="S",
                     help="delay from measurement to pitch [s]: one plant step plus the pitch actuator's lag "
                          "(default 0.1)")
    ipc.add_argument("--dt", type=_POSITIVE, default=0.01, metavar="S", help="controller step [s] (default 0.01)")
    ipc.add_argument("--linear-models", metavar="FILE.npz",
                     help="the plant's Coleman-frame models (hawt linearize; default: the turbine's, if it has them)")
    ipc.add_argument("--measured", action="store_true", help="the measured static response only, no linear models")
    ipc.add_argument("-o", "--output", metavar="FILE", help="default: the turbine's ipc tuning file")
    ipc.add_argument("--retuned-output", metavar="FILE", help="default: the turbine's ipc_retuned tuning file, or "
                     "beside -o FILE as FILE_retuned.yaml")
    ipc.add_argument("--retuned-only", action="store_true",
                     help="only derive the retuned 1P controller from the existing --output file")
    ipc.set_defaults(run=_cmd_design_ipc)

    turbine = commands.add_parser("turbine", help="import an OpenFAST deck as a turbine definition, or summarise one")
    turbine_commands = turbine.add_subparsers(dest="turbine_action", required=True, metavar="ACTION")
    importing = turbine_commands.add_parser(
        "import", help="convert an OpenFAST deck (.fst and the files it names) into DIR/turbine.yaml and airfoils/",
        description="Read the deck with openfast-io (ElastoDyn, AeroDyn, ServoDyn and the ROSCO DISCON.IN it "
                    "names), convert what the plant models into the hawt turbine definition, each value with its "
                    "source file and key, and list what is approximated and what the plant does not model. A "
                    "missing file or an option the plant cannot honour is refused, naming the file and key.")
    importing.add_argument("deck", metavar="DECK.fst")
    importing.add_argument("-o", "--output", metavar="DIR", help="folder for turbine.yaml and airfoils/ (default: "
                                                                 "the deck's name)")
    importing.set_defaults(run=_cmd_turbine_import)
    show = turbine_commands.add_parser(
        "show", help="rated values, Cp-max and optimal tip-speed ratio (the plant's BEM), first modes")
    show.add_argument("turbine", metavar="T", help="a turbine.yaml, its folder, or a packaged turbine's name "
                                                   "(nrel_5mw, nrel_5mw_two_bladed, nrel_5mw_two_bladed_downwind)")
    show.set_defaults(run=_cmd_turbine_show)

    validate = commands.add_parser(
        "validate", help="the turbine's cases side by side in OpenFAST and in hawt, ROSCO on both, and a report",
        description="Run each case in OpenFAST (the turbine's own deck, with only TMax, the wind, the initial "
                    "state, the controller and the outputs changed) and in hawt's validation graph (plant, ROSCO, mbc) in process, with the "
                    "same ROSCO library and DISCON.IN and the same wind (turbulent: the plant's field as a TurbSim "
                    ".bts both read), analyse both with hawt's analysis over the same window, and write "
                    "validation.md, index.html with plots and validation.json. Cases: steady-V or turbulent-V "
                    "(default: steady-8 steady-11.4 steady-18 turbulent-18).")
    validate.add_argument("turbine", metavar="T", help="nrel_5mw, or the folder hawt turbine import wrote")
    validate.add_argument("--openfast", metavar="PATH", help="OpenFAST executable (default: $HAWT_OPENFAST)")
    validate.add_argument("--case", action="append", default=[], metavar="NAME",
                          help="run this case (repeatable): steady-V or turbulent-V, V in m/s")
    validate.add_argument("--duration", type=_POSITIVE, metavar="S", help="simulated seconds per case (default: "
                                                                          "160 steady, 600 turbulent)")
    validate.add_argument("-o", "--output", metavar="DIR", help="report folder (default: validation-T)")
    validate.add_argument("-p", dest="param", action="append", default=[], metavar="NODE.PARAM:=VALUE",
                          help="a parameter of hawt's validation graph (e.g. -p plant.skewed_wake:=false)")
    validate.set_defaults(run=_cmd_validate)

    transfer = commands.add_parser(
        "transfer", help="Zalkind & Pao's load-transfer model (blade -> hub -> main bearing -> yaw bearing -> tower) "
                         "fitted over recorded steady runs",
        description="Fit the complex affine transfer m2 = gain*m1 + offset (Zalkind & Pao 2019 eqs. 8-11) of each "
                    "link of the load chain over the last revolutions of each bag (one steady run per wind speed), "
                    "separately for region II and III (by the collective pitch against --fine-pitch).")
    transfer.add_argument("bags", nargs="+", metavar="FILE.mcap")
    transfer.add_argument("--fine-pitch", type=float, default=0.0, help="region boundary: collective pitch [rad]")
    transfer.add_argument("--json", action="store_true", help="print the fits as JSON")
    transfer.set_defaults(run=_cmd_transfer)

    campaign = commands.add_parser(
        "campaign", help="a design-load-case campaign (speeds x seeds x controllers) on Dask workers, lifetime loads",
        description="Run every case of CAMPAIGN.yaml (wind-speed bins x seeds x controller configurations) on the "
                    "in-process engine, on a local Dask cluster or an existing one; store each case's numbers, skip "
                    "those already stored (rerun to resume), and write cases.parquet/.csv, lifetime.csv (Miner-"
                    "consistent lifetime DELs over the site's wind distribution, AEP) and report.html.")
    campaign.add_argument("campaign", metavar="CAMPAIGN.yaml", help="the campaign file")
    campaign.add_argument("-o", "--output", metavar="DIR", help="results folder (default: the file's name)")
    campaign.add_argument("--workers", type=int, help="local worker processes (default: the CPU count)")
    campaign.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="run on this Dask scheduler's workers")
    campaign.add_argument("--bags", action="store_true", help="also record every case to DIR/bags/*.mcap")
    campaign.set_defaults(run=_cmd_campaign)

    demo = commands.add_parser(
        "demo", help="run the baseline and IPC graphs on the same turbulent wind and compare their loads",
        description="Runs the baseline graph (plant, cpc, mbc) and the IPC graph with 1P+2P (+ ipc_h1, ipc_h2), "
                    "one process per node, in lockstep on the same IEC turbulent wind, records both to MCAP and "
                    "prints the headline of the load comparison (blade, hub and tower DEL changes, pitch activity, "
                    "speed and power held) and the report with every number.")
    demo.add_argument("--duration", type=_POSITIVE, default=60.0, metavar="S", help="simulated seconds per run")
    demo.add_argument("--wind-speed", type=float, default=18.0, metavar="M_PER_S", help="mean hub wind speed")
    demo.add_argument("--seed", type=int, default=1, help="turbulence seed")
    demo.add_argument("--output", default="bags", metavar="DIR", help="folder for the run's bags and report")
    demo.set_defaults(run=_cmd_demo)
    return parser


def parse_command_line(argv: Optional[List[str]] = None) -> argparse.Namespace:
    """The parsed command; a graph's NAME:=VALUE arguments may come before or after the options."""
    parser = _parser()
    args, extra = parser.parse_known_args(argv)
    if extra and getattr(args, "arguments", None) is not None and all(":=" in word for word in extra):
        args.arguments += extra
    elif extra:
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    if getattr(args, "record_optional", False) and not args.record:
        parser.error("--record-optional: needs --record")
    return args


def main(argv: Optional[List[str]] = None) -> int:
    args = parse_command_line(argv)
    try:
        return args.run(args)
    except (GraphError, BagError, SchedulingError, ViewOptionError) as error:
        print(f"hawt {args.command}: {error}", file=sys.stderr)
        return 2
    except RuntimeError as error:
        print(f"hawt {args.command}: {error}", file=sys.stderr)
        return 1
    except BrokenPipeError:
        # The reader went away (``hawt bag info … | head``): what it wanted it has; end quietly, and keep
        # Python from failing again when it flushes stdout at exit.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    sys.exit(main())
