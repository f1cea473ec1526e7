"""The package layers of docs/architecture.md §2: cores import no rclpy, and every package declares what it imports."""
import ast
import subprocess
import sys
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("hawt_core", "hawt_node", "hawt_plant", "hawt_controllers", "hawt_analysis", "hawt_bag", "hawt_tools")
ROS_MODULES = {
    "hawt_node": {"node_main", "events", "parameters", "qos", "recording", "writer_matching", "command_senders"},
    "hawt_plant": {"plant_node", "description_node"},
    "hawt_controllers": {"controller_node", "cpc_node", "ipc_node", "blade_sine_node", "mbc_node",
                         "controller_manager_node", "switch_listener", "repetitive_ipc_node",
                         "repetitive_cpc_node", "coleman_excitation_node", "lqg_ipc_node", "discon_node",
                         "main_bearing_ipc_node"},
    "hawt_bag": {"recorder", "replayer"},
    "hawt_tools": {"launcher", "launch_events", "recording", "controller_client", "graph_info", "example_nodes",
                   "view_node"},
}
"""Modules that are ROS nodes or node plumbing; every other module of a package is a core or a library."""
ROS_DISTRIBUTION = ("rclpy", "rcl_interfaces", "lifecycle_msgs", "rosgraph_msgs", "builtin_interfaces", "std_msgs",
                    "ament_index_python")


def _modules(package: str):
    return sorted(path for path in (ROOT / package / package).glob("*.py") if path.name != "__init__.py")


def test_cores_and_libraries_import_no_rclpy():
    """A fresh interpreter imports every module that is not a node or node plumbing, and has no rclpy loaded."""
    names = [f"{package}.{path.stem}" for package in PACKAGES for path in _modules(package)
             if path.stem not in ROS_MODULES.get(package, ())]
    code = ("import importlib, sys\n"
            f"for name in {names!r}:\n"
            "    importlib.import_module(name)\n"
            "    if 'rclpy' in sys.modules:\n"
            "        sys.exit(f'importing {name} loaded rclpy')\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr[-2000:]


def _imported(path: Path) -> set:
    tree = ast.parse(path.read_text())
    roots = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            roots |= {alias.name.split(".")[0] for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            roots.add(node.module.split(".")[0])
    return roots


@pytest.mark.parametrize("package", PACKAGES)
def test_package_xml_declares_every_hawt_and_ros_package_the_package_imports(package):
    """Each hawt_* and ROS package a module imports (at any depth of the module) is an exec_depend of package.xml."""
    declared = {element.text for element in ElementTree.parse(ROOT / package / "package.xml").getroot()
                if element.tag in ("exec_depend", "depend")}
    imported = set().union(*(_imported(path) for path in _modules(package)))
    needed = {name for name in imported if name != package and (name.startswith("hawt_") or name in ROS_DISTRIBUTION)}
    assert needed <= declared, f"{package}/package.xml lacks {sorted(needed - declared)}"
