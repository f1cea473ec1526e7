"""hawt's own DISCON host (hawt_controllers.discon.library, ctypes) driving libhawt_discon.so against a bridge started
as a user starts it: the helpers the bridge's tests share (tests/hawt_tools/test_discon_bridge.py, on the
in-process engine, and test_bridge_node.py, on the ROS graph)."""
import subprocess
import sys
from pathlib import Path

from hawt_controllers.discon.library import DisconInputs, DisconLibrary
from hawt_tools.discon_bridge import bridge_library
from hawt_tools.graph_file import find_graph, load_graph, package_prefix


def graph(name: str, arguments: dict = None):
    """The installed graph ``name`` with its launch ``arguments``."""
    return load_graph(find_graph(name), dict(arguments or {}), package_prefix)


def bridge_file(folder: Path, graph_name: str = "baseline", extra: str = "", name: str = "bridge") -> Path:
    """A bridge file ``NAME.txt`` in ``folder`` for ``graph_name``, its socket beside it, timeout 5 s, ``extra``
    lines after."""
    path = folder / f"{name}.txt"
    path.write_text(f"# test bridge\nsocket = {folder / (name + '.sock')}\ngraph = {graph_name}\ntimeout = 5\n{extra}")
    return path


def start_bridge(path: Path, in_process: bool = True, *options: str) -> subprocess.Popen:
    """``python -m hawt_tools.discon_bridge [--in-process] FILE`` (as ``hawt bridge [--in-process] --file FILE``), or
    with ``options`` ``hawt bridge OPTIONS --file FILE``."""
    command = [sys.executable, "-m", "hawt_tools.cli", "bridge", *options, "--file", str(path)] if options else \
        [sys.executable, "-m", "hawt_tools.discon_bridge", str(path)]
    return subprocess.Popen(command + ["--in-process"] * in_process, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)


def listening(bridge: subprocess.Popen) -> subprocess.Popen:
    """Wait for the bridge's first line, which it prints once it listens."""
    line = bridge.stderr.readline()
    assert "listening on" in line, line
    return bridge


def host(path: Path, description, individual: bool = False) -> DisconLibrary:
    """hawt's DISCON host loading libhawt_discon.so with the bridge file ``path``, for the plant ``description``'s
    blades, dt and pitch limits (record 28 = 1 with ``individual``)."""
    d = description
    return DisconLibrary(bridge_library(), path, d.blades, d.dt, (d.min_pitch, d.max_pitch, d.max_pitch_rate),
                         individual_pitch=individual)


def inputs(o) -> DisconInputs:
    """The host's inputs of one call: a plant output's measurements."""
    return DisconInputs(o.time, o.pitch, o.generator_speed, o.rotor_speed, o.generator_torque, o.electrical_power,
                        o.aero_torque * o.rotor_speed, o.hub_wind_speed, o.root_moment_oop, o.root_moment_ip,
                        o.azimuth, o.tower_top_fa_accel, o.tower_top_ss_accel, o.hub_tilt_moment, o.hub_yaw_moment)
