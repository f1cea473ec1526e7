"""The layers of docs/architecture.md §2: every import of every module goes where the table allows, layers without
ROS load no rclpy, and every package declares what it imports."""
import ast
import re
import subprocess
import sys
import xml.etree.ElementTree as ElementTree
from pathlib import Path
from typing import Dict, List, Set, Tuple

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("hawt_core", "hawt_node", "hawt_plant", "hawt_controllers", "hawt_analysis", "hawt_bag", "hawt_tools")
ROS_PACKAGES = ("rclpy", "rcl_interfaces", "lifecycle_msgs", "rosgraph_msgs", "builtin_interfaces", "std_msgs",
                "hawt_msgs")
"""What a layer without ROS must not import (ament_index_python, a plain index lookup, is not among them)."""
ROS_DISTRIBUTION = (*ROS_PACKAGES[:-1], "ament_index_python")


def _layers() -> Dict[str, Tuple[Tuple[str, ...], Set[str], bool]]:
    """docs/architecture.md's table: layer -> (module prefixes, layers it may import, whether it may use ROS)."""
    text = (ROOT / "docs" / "architecture.md").read_text()
    rows = re.search(r"^\| layer \| modules \| may import \| ROS \|\n\|[-|]+\|\n((?:\|.*\|\n)+)", text, re.M)
    assert rows, "docs/architecture.md has no table '| layer | modules | may import | ROS |'"
    layers = {}
    for line in rows.group(1).splitlines():
        name, modules, allowed, ros = (cell.strip() for cell in line.strip("|").split("|"))
        layers[name] = (tuple(re.findall(r"`([\w.]+)`", modules)),
                        {a.strip() for a in allowed.split(",") if a.strip()}, ros == "yes")
    return layers


LAYERS = _layers()


def _module_names() -> Dict[str, Path]:
    """Every module of the packages: dotted name -> file (a package's ``__init__`` that is only its docstring is
    no module of any layer)."""
    names = {}
    for package in PACKAGES:
        for path in (ROOT / package / package).rglob("*.py"):
            if path.name == "__init__.py" and len(ast.parse(path.read_text()).body) <= 1:
                continue
            parts = path.relative_to(ROOT / package).with_suffix("").parts
            names[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return names


MODULES = _module_names()


def layer_of(module: str) -> str:
    """The layer whose modules name ``module`` most specifically."""
    best = max(((len(prefix), layer) for layer, (prefixes, _, _) in LAYERS.items() for prefix in prefixes
                if module == prefix or module.startswith(prefix + ".")), default=(0, ""))
    return best[1]


def _imports(module: str, path: Path) -> Set[str]:
    """What ``module`` imports, at any depth (inside functions too), relative imports resolved."""
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = ".".join(package.split(".")[:len(package.split(".")) - node.level + 1]) if node.level else ""
            found.add(".".join(p for p in (base, node.module or "") if p))
    return found


def test_every_module_has_a_layer():
    assert not [m for m in MODULES if not layer_of(m)], "modules docs/architecture.md §2 places in no layer"


def test_every_layer_the_table_allows_exists():
    unknown = {a for _, allowed, _ in LAYERS.values() for a in allowed} - set(LAYERS)
    assert not unknown, f"the table allows imports of layers it does not have: {sorted(unknown)}"


@pytest.mark.parametrize("layer", list(LAYERS))
def test_each_import_goes_where_the_table_allows(layer):
    """A module imports its own layer's modules and those of the layers its row allows; a layer without ROS imports
    no ROS package, message package or node plumbing."""
    _, allowed, ros = LAYERS[layer]
    wrong: List[str] = []
    for module, path in MODULES.items():
        if layer_of(module) != layer:
            continue
        for imported in _imports(module, path):
            root = imported.split(".")[0]
            if root in PACKAGES:
                target = layer_of(imported)
                if target and target != layer and target not in allowed:
                    wrong.append(f"{module} imports {imported} ({target})")
            elif root in ROS_PACKAGES and not ros:
                wrong.append(f"{module} imports {imported} (ROS)")
    assert not wrong, wrong


def test_layers_without_ros_load_no_rclpy():
    """A fresh interpreter imports every module of every layer without ROS, and has no rclpy loaded."""
    names = sorted(m for m in MODULES if not LAYERS[layer_of(m)][2])
    code = ("import importlib, sys\n"
            f"for name in {names!r}:\n"
            "    importlib.import_module(name)\n"
            "    if 'rclpy' in sys.modules:\n"
            "        sys.exit(f'importing {name} loaded rclpy')\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr[-2000:]


def test_hawt_run_loads_no_ros():
    """``hawt run ipc`` from start to finish, and the engines a campaign worker imports, leave rclpy, the message
    packages and every node module out of the process."""
    code = ("import sys\n"
            "import hawt_tools.in_process, hawt_tools.campaign\n"
            "from hawt_tools.cli import main\n"
            "code = main(['run', 'ipc', 'duration:=0.5'])\n"
            "loaded = sorted(m for m in sys.modules if m.split('.')[0] in "
            f"{ROS_PACKAGES!r} or m.startswith(('hawt_node', 'hawt_controllers.ros')) or m.endswith('_node'))\n"
            "sys.exit(f'exit {code}; loaded {loaded}' if code or loaded else 0)\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, (result.stderr or result.stdout)[-2000:]


@pytest.mark.parametrize("package", PACKAGES)
def test_package_xml_declares_exactly_the_hawt_packages_the_package_imports_and_every_ros_one(package):
    """Each hawt_* and ROS package a module imports (at any depth of the module) is an exec_depend of package.xml,
    and no hawt_* package is declared that no module imports (the build order shows the layers)."""
    declared = {element.text for element in ElementTree.parse(ROOT / package / "package.xml").getroot()
                if element.tag in ("exec_depend", "depend")}
    imported = {name.split(".")[0] for module, path in MODULES.items() if module.split(".")[0] == package
                for name in _imports(module, path)}
    needed = {name for name in imported if name != package and (name.startswith("hawt_") or name in ROS_DISTRIBUTION)}
    assert needed <= declared, f"{package}/package.xml lacks {sorted(needed - declared)}"
    unused = {name for name in declared if name.startswith("hawt_") and name not in imported}
    assert not unused, f"{package}/package.xml declares {sorted(unused)}, which it does not import"
