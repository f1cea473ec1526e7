"""hawt graphs as OpenFAST's controller through libhawt_discon.so (issue 33), and what a DISCON call costs.

Measured one after the other on this machine:
- the channel alone: hawt's ctypes DISCON host calls libhawt_discon.so, which sends each call over the Unix
  socket to a bridge that answers at once without a graph (an echo of fixed commands): the round trip per call;
- the same host against the bridge with the ``baseline`` graph, in process (``--in-process``) and on the ROS graph
  (``hawt bridge``'s default: the graph's nodes in their processes, lockstep over DDS): the cost per call with the
  graph stepped;
- ``hawt run baseline`` in process: the cost per step of the same graph on hawt's own plant, for comparison;
- with ``$HAWT_OPENFAST`` (``../shared/tools/openfast/`` has one; its README says how to install it): OpenFAST on the
  NREL 5 MW deck (the inputs ``hawt validate`` writes, steady 18 m/s, shear 0.2) with ServoDyn's DLL_FileName
  pointed at libhawt_discon.so for the ``baseline`` and the ``ipc`` graph, and with ROSCO: mean rotor speed and
  power against rated, the blade-root out-of-plane 1P and DELs, and OpenFAST's wall time (bridge against ROSCO);
  both graphs on hawt's plant beside them (in process), with the changes of ipc against baseline on both plants;
- the same on the plant's own class B turbulent field at 18 m/s (seed 1) written as a TurbSim ``.bts`` that both
  plants read (``--turbulent-duration``, the first 60 s not analysed);
- OpenFAST's wall time on the steady case with ROSCO, the baseline and the ipc bridge in process, and the baseline
  bridge on the ROS graph, run in turn ``--repeat`` times (the shortest of each: the machine is shared);
- one live switch during an OpenFAST run through the ROS-graph bridge: the ``switching`` graph on the steady case,
  ``hawt switch --activate ipc_h1`` once OpenFAST reports ``--switch-at`` s; the step the switch answered, and the
  blade-root 1P and the blades' pitch spread on OpenFAST before and after it;
- the ``ipc`` run again with its bridge SIGKILLed at t = 10 s: how long OpenFAST takes to stop, and what it says.

Usage: ./hawt bench bridge [--duration S] [--turbulent-duration S] [--repeat N] [--calls N] [--switch-at S]
                          [--keep DIR]
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

CASE = {"wind_type": "steady", "wind_speed": "18", "shear_exponent": "0.2"}
"""Case "steady 18 m/s, shear 0.2": the graphs' arguments and OpenFAST's inflow."""
ANALYSED = 60.0
"""The last seconds of the steady case that are analysed [s]."""
TURBULENT_START = 60.0
"""The first seconds of the turbulent case that are not analysed [s] (the start rings)."""

_ECHO = """
import socket, sys
from hawt_tools.discon_bridge import REQUEST, encode_reply, listen
server = listen(sys.argv[1])
print("listening", file=sys.stderr, flush=True)
connection, _ = server.accept()
reply = encode_reply((0.1, 0.1, 0.1), 43000.0, (1.57, 0.14))
while True:
    data = connection.recv(REQUEST.size + 1)
    if not data:
        break
    connection.sendall(reply)
"""


def _graph(name: str, arguments: dict = None):
    from hawt_tools.graph_file import find_graph
    from hawt_tools.graph_file import load_graph
    from hawt_tools.graph_file import package_prefix

    return load_graph(find_graph(name), dict(arguments or CASE), package_prefix)


def _inputs(o):
    from hawt_controllers.discon.library import DisconInputs

    return DisconInputs(o.time, o.pitch, o.generator_speed, o.rotor_speed, o.generator_torque, o.electrical_power,
                        o.aero_torque * o.rotor_speed, o.hub_wind_speed, o.root_moment_oop, o.root_moment_ip,
                        o.azimuth, o.tower_top_fa_accel, o.tower_top_ss_accel, o.hub_tilt_moment, o.hub_yaw_moment)


def _listening(command: list) -> subprocess.Popen:
    """Start a bridge (or the echo) and wait for its first line, which it prints once it listens."""
    process = subprocess.Popen(command, stderr=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    line = process.stderr.readline()
    if "listening" not in line:
        sys.exit(f"bench bridge: {' '.join(command)} did not start: {line}{process.stderr.read()[-2000:]}")
    return process


def _bridge_file(folder: Path, graph: str, name: str = None) -> Path:
    """A bridge file ``NAME.bridge`` in ``folder`` for ``graph`` on the steady case, its socket beside it."""
    name = name or graph
    path = folder / f"{name}.bridge"
    arguments = " ".join(f"{k}:={v}" for k, v in CASE.items())
    path.write_text(f"socket = {folder / (name + '.sock')}\ngraph = {graph}\narguments = {arguments}\ntimeout = 30\n")
    return path


BRIDGES = {"echo": [sys.executable, "-c", _ECHO], "in_process": [sys.executable, "-m", "hawt_tools.discon_bridge",
                                                                   "--in-process"],
           "ros_graph": [sys.executable, "-m", "hawt_tools.discon_bridge"]}
"""The command lines (then the socket or bridge file) of the echo, the in-process bridge and the ROS-graph bridge."""


def host_calls(folder: Path, calls: int, bridge: str) -> float:
    """Wall time per DISCON call [s] of hawt's ctypes host stepping the library ``calls`` times against the echo or
    the ``baseline`` bridge (``bridge``, a key of :data:`BRIDGES`), on the operating point of the baseline graph's
    step 0."""
    from hawt_controllers.discon.library import DisconLibrary
    from hawt_tools.discon_bridge import bridge_library
    from hawt_tools.in_process import build_run

    run = build_run(_graph("baseline"))
    path = _bridge_file(folder, "baseline")
    echo = bridge == "echo"
    process = _listening(BRIDGES[bridge] + [str(folder / "baseline.sock") if echo else str(path)])
    d = run.description
    host = DisconLibrary(bridge_library(), path, d.blades, d.dt, (d.min_pitch, d.max_pitch, d.max_pitch_rate))
    inputs = _inputs(run.output)
    host.step(inputs)  # the first call builds the graph
    start = time.perf_counter()
    for _ in range(calls):
        host.step(inputs)
    wall = (time.perf_counter() - start) / calls
    if echo:
        process.kill()
    else:
        host.close()
    process.wait()
    return wall


def in_process_step(steps: int) -> float:
    """Wall time per step [s] of ``hawt run baseline`` in process (hawt's plant included)."""
    from hawt_tools.in_process import build_run

    run = build_run(_graph("baseline"))
    start = time.perf_counter()
    for _ in range(steps):
        run.step()
    return (time.perf_counter() - start) / steps


class Case:
    """A wind case on both plants: steady 18 m/s with shear 0.2, or the plant's own class B turbulent field at
    18 m/s (seed ``seed``) written as a TurbSim ``.bts`` that OpenFAST and hawt's plant both read."""

    def __init__(self, folder: Path, duration: float, turbulent: bool = False, seed: int = 1) -> None:
        self.duration, self.turbulent = duration, turbulent
        self.name = f"turbulent-18-seed{seed}" if turbulent else "steady-18"
        self.arguments, self.parameters, self.bts = dict(CASE), [], None
        self.window = (duration - ANALYSED, duration) if not turbulent else (TURBULENT_START, duration)
        if turbulent:
            from hawt_plant.bts import write_bts
            from hawt_plant.inflow import InflowSettings, make_wind
            from hawt_plant.turbine import nrel_5mw
            from hawt_tools.openfast_case import deck_hub_height, deck_of

            turbine = nrel_5mw()
            wind = make_wind(InflowSettings(kind="turbulent", wind_speed=18.0, shear_exponent=0.2,
                                            hub_height=turbine.hub_height, rotor_radius=turbine.rotor.tip_radius,
                                            turbulence_class="B", seed=seed, field_duration=max(600.0, duration)))
            if abs(deck_hub_height(deck_of("nrel_5mw")) - wind.hub_height) > 1e-3:
                sys.exit("bench bridge: the NREL 5 MW deck's hub is not the plant's")
            self.bts = folder / f"{self.name}.bts"
            write_bts(self.bts, wind, f"bench bridge: IEC Kaimal class B, 18 m/s, seed {seed}", tower=True)
            self.arguments["wind_type"] = "bts"
            self.parameters = [f"plant.bts_file:={self.bts}"]
        self.arguments["duration"] = f"{duration:g}"

    def bridge_file(self, folder: Path, graph: str, bridge: str = "in_process", arguments: str = "") -> Path:
        """The bridge file of ``graph`` on this case (its socket beside it), named after the ``bridge`` too, with more
        launch ``arguments`` if given."""
        name = f"{self.name}-{graph}" + ("-ros" if bridge == "ros_graph" else "")
        path = folder / f"{name}.bridge"
        arguments = " ".join([f"{k}:={v}" for k, v in self.arguments.items()] + ([arguments] if arguments else []))
        path.write_text(f"socket = {folder / (name + '.sock')}\ngraph = {graph}\narguments = {arguments}\n"
                        f"parameters = {' '.join(self.parameters)}\ntimeout = 30\n")
        return path

    def hawt_run(self, graph: str):
        """The graph built in process on hawt's plant for this case, at step 0."""
        from hawt_tools.in_process import build_run
        from hawt_tools.node_parameters import parse_overrides

        built = _graph(graph, self.arguments)
        return build_run(built, parse_overrides(built, self.parameters))

    def write_openfast(self, folder: Path, name: str, library: Path, infile: Path):
        """The NREL 5 MW deck for this case with ``library`` and ``infile`` as ServoDyn's DLL and its input, started
        at the baseline graph's operating point of step 0 (as ``hawt validate`` does)."""
        from hawt_analysis.openfast_output import openfast_channel_names
        from hawt_tools.openfast_case import CaseInputs, deck_of, write_case

        output = self.hawt_run("baseline").output
        inputs = CaseInputs(
            duration=self.duration, wind_speed=18.0, shear_exponent=0.2, rotor_speed=float(output.rotor_speed),
            pitch=tuple(float(p) for p in output.pitch), azimuth=float(output.azimuth),
            tower_top=(float(output.tower_top_fa_disp), float(output.tower_top_ss_disp)), discon_library=library,
            discon_input=infile, channels=openfast_channel_names(3), bts_file=self.bts)
        return write_case(deck_of("nrel_5mw"), folder / name, name, inputs)


def openfast_bridged(executable: Path, folder: Path, case: Case, graph: str, bridge: str = "in_process",
                     progress=lambda t, total: None, arguments: str = "") -> tuple:
    """OpenFAST with libhawt_discon.so and ``graph`` (with more launch ``arguments``) on ``case``, bridged by
    ``bridge`` (``in_process`` or ``ros_graph``); ``progress(t, TMax)`` as OpenFAST reports. Its wall time [s] and
    channels."""
    from hawt_analysis.openfast_output import read_openfast_output
    from hawt_tools.discon_bridge import bridge_library
    from hawt_tools.openfast_case import output_of, run_openfast

    path = case.bridge_file(folder, graph, bridge, arguments)
    written = case.write_openfast(folder, path.stem, bridge_library(), path)
    bridge = _listening(BRIDGES[bridge] + [str(path)])
    try:
        wall = run_openfast(executable, written.fst, progress)
    finally:
        out, err = bridge.communicate(timeout=120)
    if bridge.returncode != 0:
        sys.exit(f"bench bridge: the {graph} bridge failed (exit {bridge.returncode}): {err[-2000:]}")
    return wall, read_openfast_output(output_of(written.fst))


def openfast_rosco(executable: Path, folder: Path, case: Case) -> tuple:
    """OpenFAST with ROSCO (the rosco wheel's library and the NREL 5 MW DISCON.IN) on ``case``: wall time [s] and
    channels."""
    from hawt_analysis.openfast_output import read_openfast_output
    from hawt_controllers.discon.rosco_input import rosco_files, write_private_input
    from hawt_controllers.design.tunings import tuning_file
    from hawt_tools.openfast_case import output_of, run_openfast

    name = f"{case.name}-rosco"
    (folder / name).mkdir(parents=True, exist_ok=True)
    discon = write_private_input(tuning_file("nrel_5mw", "discon"), folder / name / "DISCON.IN", {})
    written = case.write_openfast(folder, name, rosco_files()[0], discon)
    return run_openfast(executable, written.fst), read_openfast_output(output_of(written.fst))


def hawt_plant(folder: Path, case: Case, graph: str) -> tuple:
    """``hawt run GRAPH`` on ``case`` (hawt's plant, in process): wall time [s] and channels."""
    from hawt_bag.plant_run import load_plant_run
    from hawt_bag.reader import BagReader
    from hawt_tools.in_process import step_run

    bag = folder / f"{case.name}-{graph}-hawt.mcap"
    bag.unlink(missing_ok=True)
    start = time.monotonic()
    step_run(case.hawt_run(graph), case.duration, bag)
    wall = time.monotonic() - start
    with BagReader(bag) as reader:
        return wall, load_plant_run(reader).channels


def openfast_bridge_killed(executable: Path, folder: Path, case: Case, at: float = 10.0) -> tuple:
    """OpenFAST with the ``ipc`` bridge SIGKILLed once OpenFAST reports ``at`` s: OpenFAST's last lines (its
    error, the library's message) and the wall time [s] from the kill to OpenFAST's exit."""
    from hawt_tools.discon_bridge import bridge_library
    from hawt_tools.openfast_case import OpenFastFailed, run_openfast

    path = case.bridge_file(folder, "ipc")
    killed_path = path.with_name(f"{path.stem}-killed.bridge")
    killed_path.write_text(path.read_text().replace(".sock", "-killed.sock"))
    written = case.write_openfast(folder, killed_path.stem, bridge_library(), killed_path)
    bridge = _listening(BRIDGES["in_process"] + [str(killed_path)])
    killed = []

    def progress(t: float, total: float) -> None:
        if t >= at and not killed:
            bridge.kill()
            killed.append(time.monotonic())

    try:
        run_openfast(executable, written.fst, progress)
    except OpenFastFailed as failure:
        return str(failure).split("): ", 1)[-1], time.monotonic() - killed[0] if killed else float("nan")
    finally:
        bridge.kill()
        bridge.wait()
    sys.exit("bench bridge: OpenFAST ran to the end with its bridge killed")


def figures(channels: dict, window: tuple) -> dict:
    """Over ``window`` (start, end) [s]: mean rotor speed [rad/s] and power [W]; the blade-root out-of-plane 1P
    amplitude [N*m], its DEL (m = 10) and the hub tilt, yaw and tower-base fore-aft DELs (m = 4) [N*m], blade means;
    the largest spread of the blades' pitch [rad] and the pitch travel [rad per blade]."""
    from hawt_analysis.summary import summarize

    inside = (channels["time"] >= window[0] - 1e-9) & (channels["time"] <= window[1] + 1e-9)
    s = summarize({k: np.asarray(v)[inside] for k, v in channels.items()})
    blades = [k for k in s["del"] if k.startswith("root_moment_oop_")]
    one_p = np.mean([s["harmonics"][k]["amplitude"][0] for k in blades])
    return {"rotor_speed": s["rotor_speed"]["mean"], "power": s["power"]["mean"], "one_p": float(one_p),
            "root_del": float(np.mean([s["del"][k]["value"] for k in blades])),
            **{k: s["del"][k]["value"] for k in ("hub_tilt_moment", "hub_yaw_moment", "tower_base_fa_moment")},
            "pitch_spread": float(np.max(np.ptp(np.asarray(channels["pitch"])[inside], axis=1))),
            "travel": float(np.mean(s["pitch"]["travel_rad"]["per_blade"]))}


def _line(label: str, wall: float, duration: float, f: dict, rated) -> str:
    return (f"{label:34s} {wall:6.1f} s wall ({duration / wall:5.2f}x rt)  speed "
            f"{f['rotor_speed'] / rated.rated_rotor_speed:.4f}  power {f['power'] / rated.rated_power:.4f}  "
            f"1P {f['one_p'] / 1e6:6.3f}  root DEL {f['root_del'] / 1e6:6.3f}"
            f"  tilt/yaw DEL {f['hub_tilt_moment'] / 1e6:5.3f}/{f['hub_yaw_moment'] / 1e6:5.3f}"
            f"  tower fa DEL {f['tower_base_fa_moment'] / 1e6:6.3f}"
            f"  pitch spread {np.degrees(f['pitch_spread']):5.2f} deg, travel {np.degrees(f['travel']):6.1f} deg/blade")


def compare(executable: Path, folder: Path, case: Case) -> dict:
    """ROSCO, the baseline and the ipc graph on OpenFAST, and both graphs on hawt's plant, on ``case``; prints a line
    each and the changes of ipc against baseline on both plants. Returns name -> (wall, figures)."""
    from hawt_plant.turbine import nrel_5mw

    rated = nrel_5mw().description(0.01)
    print(f"{case.name}, {case.duration:g} s, analysed {case.window[0]:g}-{case.window[1]:g} s (speed and power: of "
          "rated; moments MN*m, DELs m = 10 blade root, 4 steel):", flush=True)
    runs = {}
    for name in ("rosco", "baseline", "ipc", "hawt baseline", "hawt ipc"):
        if name == "rosco":
            wall, channels = openfast_rosco(executable, folder, case)
        elif name.startswith("hawt "):
            wall, channels = hawt_plant(folder, case, name.split()[1])
        else:
            wall, channels = openfast_bridged(executable, folder, case, name)
        runs[name] = (wall, figures(channels, case.window))
        label = name.replace("hawt ", "hawt's plant + ") if name.startswith("hawt") else f"OpenFAST + {name}"
        print("  " + _line(label, wall, case.duration, runs[name][1], rated), flush=True)
    for plant, prefix in (("OpenFAST", ""), ("hawt's plant", "hawt ")):
        base, ipc = runs[prefix + "baseline"][1], runs[prefix + "ipc"][1]
        changes = ", ".join(f"{label} {ipc[key] / base[key] - 1:+.1%}" for label, key in (
            ("1P", "one_p"), ("root DEL", "root_del"), ("tilt DEL", "hub_tilt_moment"), ("yaw DEL", "hub_yaw_moment"),
            ("tower fa DEL", "tower_base_fa_moment")))
        print(f"  ipc against baseline on {plant}: {changes}", flush=True)
    for name in ("baseline", "ipc"):
        print(f"  OpenFAST speed with the {name} bridge / with ROSCO: {runs['rosco'][0] / runs[name][0]:.2f} "
              "(target >= 0.5)", flush=True)
    return runs


def speed(executable: Path, folder: Path, case: Case, repeat: int) -> None:
    """OpenFAST's wall time on ``case`` with ROSCO, the baseline and the ipc bridge, run in turn ``repeat`` times;
    prints the shortest of each and the ratios (the machine is shared: the shortest is the least disturbed)."""
    walls = {"rosco": [], "baseline": [], "ipc": [], "baseline ros graph": []}
    for _ in range(repeat):
        for name in walls:
            run = openfast_rosco(executable, folder, case) if name == "rosco" else \
                openfast_bridged(executable, folder, case, name.split()[0],
                                 "ros_graph" if name.endswith("ros graph") else "in_process")
            walls[name].append(run[0])
    best = {name: min(values) for name, values in walls.items()}
    print(f"OpenFAST wall time on {case.name} ({case.duration:g} s), shortest of {repeat} runs in turn: " +
          ", ".join(f"{name} {best[name]:.1f} s ({case.duration / best[name]:.2f}x rt; all: "
                    f"{' '.join(f'{w:.1f}' for w in walls[name])})" for name in walls), flush=True)
    for name in ("baseline", "ipc", "baseline ros graph"):
        print(f"  OpenFAST speed with the {name} bridge / with ROSCO: {best['rosco'] / best[name]:.2f} (target >= 0.5)",
              flush=True)


def live_switch(executable: Path, folder: Path, case: Case, at: float, namespace: str = "bench_switch") -> None:
    """OpenFAST through the ROS-graph bridge with the ``switching`` graph on ``case``; ``hawt switch --activate
    ipc_h1`` once OpenFAST reports ``at`` s. Prints the step the switch answered, and the blade-root 1P and the
    blades' pitch spread on OpenFAST over 30 s before it and from 10 s after it (the ramp, 2 s, and the integrator's
    rise) to the end."""
    import re

    switch = []

    def progress(t: float, total: float) -> None:
        if t >= at and not switch:
            switch.append((t, subprocess.Popen([sys.executable, "-m", "hawt_tools.cli", "switch", "--activate",
                                                "ipc_h1", "--namespace", namespace], stdout=subprocess.PIPE,
                                               stderr=subprocess.STDOUT, text=True)))

    wall, channels = openfast_bridged(executable, folder, case, "switching", "ros_graph", progress,
                                      f"namespace:={namespace}")
    if not switch:
        sys.exit(f"bench bridge: OpenFAST never reported t = {at:g} s")
    asked, process = switch[0]
    answer = process.communicate(timeout=60)[0].strip()
    found = re.search(r"at step (\d+)", answer)
    if process.returncode != 0 or not found:
        sys.exit(f"bench bridge: hawt switch failed (exit {process.returncode}): {answer}")
    effective = int(found.group(1)) * float(np.median(np.diff(channels["time"])))
    before = figures(channels, (effective - 30.0, effective))
    after = figures(channels, (effective + 10.0, case.duration))
    print(f"live switch through the ROS-graph bridge ({wall:.1f} s wall for {case.duration:g} s, "
          f"{case.duration / wall:.2f}x rt): hawt switch --activate ipc_h1 at OpenFAST t = {asked:.1f} s answered "
          f"'{answer}' (t = {effective:.2f} s); blade-root 1P {before['one_p'] / 1e6:.3f} -> "
          f"{after['one_p'] / 1e6:.3f} MN*m ({after['one_p'] / before['one_p'] - 1:+.1%}), pitch spread "
          f"{np.degrees(before['pitch_spread']):.2f} -> {np.degrees(after['pitch_spread']):.2f} deg", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=120.0, help="simulated time of the steady case [s]")
    parser.add_argument("--turbulent-duration", type=float, default=300.0,
                        help="simulated time of the turbulent case [s] (0: leave it out)")
    parser.add_argument("--calls", type=int, default=5000, help="DISCON calls timed per host measurement")
    parser.add_argument("--repeat", type=int, default=3, help="runs in turn of OpenFAST with ROSCO, the baseline "
                        "and the ipc bridge on the steady case for the speed figures (0: leave them out)")
    parser.add_argument("--switch-at", type=float, default=40.0, help="OpenFAST time of the live switch through the "
                        "ROS-graph bridge [s] (0: leave it out)")
    parser.add_argument("--keep", help="write the OpenFAST cases into this folder and keep them")
    args = parser.parse_args()
    # a socket path must stay under 108 characters: a short temporary folder
    with tempfile.TemporaryDirectory(prefix="hawt-bridge-") as temporary:
        folder = Path(args.keep or temporary).resolve()
        folder.mkdir(parents=True, exist_ok=True)
        sockets = Path(temporary)
        echo = host_calls(sockets, args.calls, "echo")
        print(f"channel round trip (ctypes host -> library -> Unix socket -> echo):  {echo * 1e6:7.1f} us per call",
              flush=True)
        bridged = host_calls(sockets, args.calls, "in_process")
        print(f"DISCON call with the baseline graph bridged in process (--in-process):  {bridged * 1e6:7.1f} us "
              "per call", flush=True)
        graph = host_calls(sockets, args.calls, "ros_graph")
        print(f"DISCON call with the baseline graph bridged on the ROS graph (lockstep over DDS): {graph * 1e6:7.1f} "
              "us per call", flush=True)
        step = in_process_step(args.calls)
        print(f"hawt run baseline, one step in process (hawt's plant included):      {step * 1e6:7.1f} us", flush=True)
        executable = os.environ.get("HAWT_OPENFAST")
        if not executable:
            print("OpenFAST: $HAWT_OPENFAST is not set (../shared/tools/openfast/install.sh DIR installs one)")
            return
        executable = Path(executable)
        steady = Case(folder, args.duration)
        runs = compare(executable, folder, steady)
        cut = 1 - runs["ipc"][1]["one_p"] / runs["baseline"][1]["one_p"]
        print(f"blade-root 1P cut by ipc against baseline on OpenFAST, {steady.name}: {cut:.1%} (target >= 90 %)")
        if args.repeat > 0:
            speed(executable, folder, steady, args.repeat)
        if args.switch_at > 0:
            live_switch(executable, folder, steady, args.switch_at)
        if args.turbulent_duration > 0:
            compare(executable, folder, Case(folder, args.turbulent_duration, turbulent=True))
        lines, after = openfast_bridge_killed(executable, folder, steady)
        print(f"ipc bridge SIGKILLed at t = 10 s: OpenFAST exited {after:.2f} s later (the library fails at the next "
              f"call; OpenFAST's exit pauses 3 s); its last lines: {lines}")
    print("load average (1, 5, 15 min): {:.2f} {:.2f} {:.2f} on {} CPUs".format(*os.getloadavg(), os.cpu_count()))


if __name__ == "__main__":
    main()
