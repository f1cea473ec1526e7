"""hawt graphs as OpenFAST's controller through libhawt_discon.so (issue 33), and what a DISCON call costs.

Measured one after the other on this machine:
- the channel alone: hawt's ctypes DISCON host calls libhawt_discon.so, which sends each call over the Unix
  socket to a bridge that answers at once without a graph (an echo of fixed commands): the round trip per call;
- the same host against the bridge with the ``baseline`` graph: the cost per call with the graph stepped;
- ``hawt run baseline`` in process: the cost per step of the same graph on hawt's own plant, for comparison;
- with ``$HAWT_OPENFAST`` (``../shared/tools/openfast/`` has one; its README says how to install it): OpenFAST on the
  NREL 5 MW deck (the inputs ``hawt validate`` writes, steady 18 m/s, shear 0.2) with ServoDyn's DLL_FileName
  pointed at libhawt_discon.so for the ``baseline`` and the ``ipc`` graph, and with ROSCO: mean rotor speed and
  power against rated, the blade-root out-of-plane 1P, and OpenFAST's wall time (bridge against ROSCO); then the
  ``ipc`` run again with its bridge SIGKILLed at t = 10 s: how long OpenFAST takes to stop, and what it says.

Usage: ./hawt bench bridge [--duration S] [--calls N] [--keep DIR]
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
"""The last seconds of a run that are analysed [s]."""

_ECHO = """
import socket, sys
from hawt_tools.discon_bridge import REQUEST, _reply, listen
server = listen(sys.argv[1])
print("listening", file=sys.stderr, flush=True)
connection, _ = server.accept()
reply = _reply((0.1, 0.1, 0.1), 43000.0, (1.57, 0.14))
while True:
    data = connection.recv(REQUEST.size + 1)
    if not data:
        break
    connection.sendall(reply)
"""


def _graph(name: str):
    from hawt_tools.cli import find_graph
    from hawt_tools.graph_file import load_graph
    from hawt_tools.launcher import package_prefix

    return load_graph(find_graph(name), dict(CASE), package_prefix)


def _inputs(o):
    from hawt_controllers.discon_library import DisconInputs

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


def _bridge_file(folder: Path, graph: str, record: str = "") -> Path:
    path = folder / f"{graph}.bridge"
    arguments = " ".join(f"{k}:={v}" for k, v in CASE.items())
    path.write_text(f"socket = {folder / (graph + '.sock')}\ngraph = {graph}\narguments = {arguments}\n"
                    f"timeout = 30\n{record}")
    return path


def host_calls(folder: Path, calls: int, echo: bool) -> float:
    """Wall time per DISCON call [s] of hawt's ctypes host stepping the library ``calls`` times against the echo or
    the ``baseline`` bridge, on the operating point of the baseline graph's step 0."""
    from hawt_controllers.discon_library import DisconLibrary
    from hawt_tools.discon_bridge import bridge_library
    from hawt_tools.in_process import build_run

    run = build_run(_graph("baseline"))
    path = _bridge_file(folder, "baseline")
    command = ([sys.executable, "-c", _ECHO, str(folder / "baseline.sock")] if echo else
               [sys.executable, "-m", "hawt_tools.discon_bridge", str(path)])
    process = _listening(command)
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


def write_openfast_case(folder: Path, name: str, duration: float, library: Path, infile: Path):
    """The NREL 5 MW deck for case steady 18 m/s, shear 0.2, with ``library`` and ``infile`` as ServoDyn's DLL and
    its input, starting at the baseline graph's operating point of step 0 (as ``hawt validate`` does)."""
    from hawt_analysis.openfast_output import openfast_channel_names
    from hawt_tools.in_process import build_run
    from hawt_tools.openfast_case import CaseInputs, deck_of, write_case

    output = build_run(_graph("baseline")).output
    inputs = CaseInputs(
        duration=duration, wind_speed=float(CASE["wind_speed"]), shear_exponent=float(CASE["shear_exponent"]),
        rotor_speed=float(output.rotor_speed), pitch=tuple(float(p) for p in output.pitch),
        azimuth=float(output.azimuth), tower_top=(float(output.tower_top_fa_disp), float(output.tower_top_ss_disp)),
        discon_library=library, discon_input=infile, channels=openfast_channel_names(3))
    return write_case(deck_of("nrel_5mw"), folder / name, name, inputs)


def openfast_bridged(executable: Path, folder: Path, graph: str, duration: float) -> tuple:
    """OpenFAST with libhawt_discon.so and ``graph``: its wall time [s] and output file."""
    from hawt_tools.discon_bridge import bridge_library
    from hawt_tools.openfast_case import output_of, run_openfast

    path = _bridge_file(folder, graph)
    written = write_openfast_case(folder, graph, duration, bridge_library(), path)
    bridge = _listening([sys.executable, "-m", "hawt_tools.discon_bridge", str(path)])
    try:
        wall = run_openfast(executable, written.fst)
    finally:
        out, err = bridge.communicate(timeout=60)
    if bridge.returncode != 0:
        sys.exit(f"bench bridge: the {graph} bridge failed (exit {bridge.returncode}): {err[-2000:]}")
    return wall, output_of(written.fst)


def openfast_bridge_killed(executable: Path, folder: Path, duration: float, at: float = 10.0) -> tuple:
    """OpenFAST with the ``ipc`` bridge SIGKILLed once OpenFAST reports ``at`` s: OpenFAST's last lines (its
    error, the library's message) and the wall time [s] from the kill to OpenFAST's exit."""
    from hawt_tools.discon_bridge import bridge_library
    from hawt_tools.openfast_case import OpenFastFailed, run_openfast

    path = _bridge_file(folder, "ipc_killed").parent / "ipc_killed.bridge"
    path.write_text(_bridge_file(folder, "ipc").read_text().replace("ipc.sock", "ipc_killed.sock"))
    written = write_openfast_case(folder, "ipc_killed", duration, bridge_library(), path)
    bridge = _listening([sys.executable, "-m", "hawt_tools.discon_bridge", str(path)])
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


def openfast_rosco(executable: Path, folder: Path, duration: float) -> tuple:
    """OpenFAST with ROSCO (the rosco wheel's library and the NREL 5 MW DISCON.IN): wall time [s] and output file."""
    from hawt_controllers.rosco_input import rosco_files, write_private_input
    from hawt_controllers.tunings import tuning_file
    from hawt_tools.openfast_case import output_of, run_openfast

    (folder / "rosco").mkdir(parents=True, exist_ok=True)
    discon = write_private_input(tuning_file("nrel_5mw", "discon"), folder / "rosco" / "DISCON.IN", {})
    written = write_openfast_case(folder, "rosco", duration, rosco_files()[0], discon)
    return run_openfast(executable, written.fst), output_of(written.fst)


def figures(outb: Path) -> dict:
    """Mean rotor speed [rad/s] and power [W] and the blade-root out-of-plane 1P amplitude [N*m] (blade mean) over
    the last :data:`ANALYSED` s."""
    from hawt_analysis.harmonics import harmonic_amplitudes
    from hawt_analysis.openfast_output import read_openfast_output

    channels = read_openfast_output(outb)
    last = channels["time"] >= channels["time"][-1] - ANALYSED
    one_p = harmonic_amplitudes(channels["root_moment_oop"][last], channels["azimuth"][last], (1,)).amplitude
    pitch = channels["pitch"][last]
    return {"rotor_speed": float(np.mean(channels["rotor_speed"][last])),
            "power": float(np.mean(channels["electrical_power"][last])), "one_p": float(np.mean(one_p)),
            "pitch_spread": float(np.max(np.ptp(pitch, axis=1)))}


def main() -> None:
    from hawt_plant.turbine import nrel_5mw

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=120.0, help="simulated time of the OpenFAST case [s]")
    parser.add_argument("--calls", type=int, default=5000, help="DISCON calls timed per host measurement")
    parser.add_argument("--keep", help="write the OpenFAST cases into this folder and keep them")
    args = parser.parse_args()
    # a socket path must stay under 108 characters: a short temporary folder
    with tempfile.TemporaryDirectory(prefix="hawt-bridge-") as temporary:
        folder = Path(args.keep or temporary)
        folder.mkdir(parents=True, exist_ok=True)
        sockets = Path(temporary)
        echo = host_calls(sockets, args.calls, echo=True)
        print(f"channel round trip (ctypes host -> library -> Unix socket -> echo):  {echo * 1e6:7.1f} us per call",
              flush=True)
        bridged = host_calls(sockets, args.calls, echo=False)
        print(f"DISCON call with the baseline graph bridged (host -> library -> bridge): {bridged * 1e6:7.1f} us "
              "per call", flush=True)
        step = in_process_step(args.calls)
        print(f"hawt run baseline, one step in process (hawt's plant included):      {step * 1e6:7.1f} us", flush=True)
        executable = os.environ.get("HAWT_OPENFAST")
        if not executable:
            print("OpenFAST: $HAWT_OPENFAST is not set (../shared/tools/openfast/install.sh DIR installs one)")
            return
        executable = Path(executable)
        d = nrel_5mw().description(0.01)
        runs = {}
        for name in ("rosco", "baseline", "ipc"):
            if name == "rosco":
                wall, outb = openfast_rosco(executable, folder, args.duration)
            else:
                wall, outb = openfast_bridged(executable, folder, name, args.duration)
            runs[name] = (wall, figures(outb))
            f = runs[name][1]
            print(f"OpenFAST + {name:8s} ({args.duration:g} s, steady 18 m/s, shear 0.2): {wall:6.1f} s wall "
                  f"({args.duration / wall:.2f}x real time); last {ANALYSED:g} s: rotor speed "
                  f"{f['rotor_speed'] / d.rated_rotor_speed:.4f} of rated, power {f['power'] / d.rated_power:.4f} of "
                  f"rated, blade-root 1P {f['one_p'] / 1e6:.3f} MN*m, largest pitch spread "
                  f"{np.degrees(f['pitch_spread']):.2f} deg", flush=True)
        cut = 1 - runs["ipc"][1]["one_p"] / runs["baseline"][1]["one_p"]
        print(f"blade-root 1P cut by ipc against baseline on OpenFAST: {cut:.1%} (target >= 90 %)")
        for name in ("baseline", "ipc"):
            print(f"OpenFAST speed with the {name} bridge / with ROSCO: {runs['rosco'][0] / runs[name][0]:.2f} "
                  "(target >= 0.5)")
        lines, after = openfast_bridge_killed(executable, folder, args.duration)
        print(f"ipc bridge SIGKILLed at t = 10 s: OpenFAST exited {after:.2f} s later (the library fails at the next "
              f"call; OpenFAST's exit pauses 3 s); its last lines: {lines}")
    print("load average (1, 5, 15 min): {:.2f} {:.2f} {:.2f} on {} CPUs".format(*os.getloadavg(), os.cpu_count()))


if __name__ == "__main__":
    main()
