"""Talking to a running graph's controller_manager from a shell: ``hawt switch`` and the controllers of ``hawt list``."""
import time
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

import rclpy
from hawt_msgs.srv import ListControllers, SwitchControllers
from rclpy.node import Node

from hawt_core.topics import LIST_CONTROLLERS, SWITCH_CONTROLLERS

__all__ = ["ControllerRow", "SwitchResult", "ControllerManagerError", "NoSuchController", "find_managers",
           "lifecycle_transition", "list_controllers", "manager_namespace", "switch_controllers"]


class ControllerManagerError(RuntimeError):
    """No controller manager answered, or the one to use is not clear."""


class NoSuchController(ControllerManagerError):
    """The graph's controller manager does not know the controller named (a typo): bad input."""


DISCOVERY_TIMEOUT = 10.0
"""[s] How long ``hawt lifecycle`` waits for the graph's controller manager to appear (discovery on a busy machine)."""


@dataclass(frozen=True)
class ControllerRow:
    """One controller as its manager lists it."""

    name: str
    type: str
    interfaces: str
    state: str


@dataclass(frozen=True)
class SwitchResult:
    ok: bool
    message: str
    effective_step: int


def find_managers(node: Node, timeout: float = 3.0) -> List[str]:
    """Namespaces of the controller managers in the graph (their list_controllers services), waiting up to ``timeout``."""
    suffix = "/" + LIST_CONTROLLERS
    deadline = time.monotonic() + timeout
    while True:
        found = sorted(name[:-len(suffix)] for name, _ in node.get_service_names_and_types() if name.endswith(suffix))
        if found or time.monotonic() > deadline:
            return found
        time.sleep(0.1)


def _call(node: Node, service_type, name: str, request, timeout: float):
    client = node.create_client(service_type, name)
    try:
        if not client.wait_for_service(timeout_sec=timeout):
            raise ControllerManagerError(f"{name}: no answer within {timeout:g} s (is the graph running?)")
        future = client.call_async(request)
        rclpy.spin_until_future_complete(node, future, timeout_sec=timeout)
        if not future.done():
            raise ControllerManagerError(f"{name}: no answer within {timeout:g} s")
        return future.result()
    finally:
        node.destroy_client(client)


def list_controllers(node: Node, namespace: str, timeout: float = 5.0) -> Tuple[ControllerRow, ...]:
    """The controllers of the manager in ``namespace`` with their claimed interfaces and lifecycle states."""
    response = _call(node, ListControllers, f"{namespace}/{LIST_CONTROLLERS}", ListControllers.Request(), timeout)
    return tuple(ControllerRow(*row) for row in zip(response.names, response.types, response.interfaces,
                                                    response.states))


def manager_namespace(namespace: str) -> str:
    """A turbine namespace as given (``wt1``, ``/wt1/``) in the form the manager's services are under (``/wt1``)."""
    return "/" + namespace.strip("/") if namespace.strip("/") else ""


def _manager(node: Node, namespace: Optional[str], timeout: float) -> str:
    """The namespace of the graph's one controller manager (given, or discovered within ``timeout`` s)."""
    if namespace is not None:
        return manager_namespace(namespace)
    managers = find_managers(node, timeout)
    if not managers:
        raise ControllerManagerError("no controller_manager in the graph (is a graph with one running, in this "
                                     "ROS_DOMAIN_ID?)")
    if len(managers) > 1:
        raise ControllerManagerError(f"several controller managers ({', '.join(managers)}): choose one with "
                                     f"--namespace")
    return managers[0]


def switch_controllers(activate: Sequence[str], deactivate: Sequence[str], strict: bool = True,
                       ramp_time: float = -1.0, at_step: int = 0, namespace: Optional[str] = None,
                       timeout: float = 10.0) -> SwitchResult:
    """Ask the graph's controller manager for one switch (DESIGN.md §5 SwitchControllers)."""
    request = SwitchControllers.Request(
        activate=list(activate), deactivate=list(deactivate), ramp_time=float(ramp_time), at_step=int(at_step),
        strictness=SwitchControllers.Request.STRICT if strict else SwitchControllers.Request.BEST_EFFORT)
    with rclpy.init():
        node = Node("_hawt_switch", start_parameter_services=False, enable_rosout=False)
        try:
            response = _call(node, SwitchControllers, f"{_manager(node, namespace, timeout)}/{SWITCH_CONTROLLERS}", request,
                             timeout)
        finally:
            node.destroy_node()
    return SwitchResult(response.ok, response.message, int(response.effective_step))


def lifecycle_transition(name: str, transition: Optional[str] = None, namespace: Optional[str] = None,
                         timeout: float = 30.0) -> Tuple[bool, str]:
    """Ask the lifecycle node ``name`` for a standard transition (None: none); (succeeded, state label after).

    ``name`` is a full node name or a plain one (looked up under the graph's controller manager's
    namespace). A controller passes ``activate``/``deactivate`` on to its controller_manager, so the
    transition takes effect at a plant step like ``hawt switch``.
    """
    from lifecycle_msgs.msg import Transition
    from lifecycle_msgs.srv import ChangeState, GetState

    with rclpy.init():
        node = Node("_hawt_lifecycle", start_parameter_services=False, enable_rosout=False)
        try:
            full = name
            if not name.startswith("/"):  # a controller of the graph's manager: one it knows (a typo is refused)
                manager = _manager(node, namespace, min(timeout, DISCOVERY_TIMEOUT))
                full = f"{manager}/{name}"
                known = [row.name for row in list_controllers(node, manager, timeout)]
                if full not in known:
                    raise NoSuchController(f"{name}: no such controller (known: {', '.join(known)})")
            ok = True
            if transition is not None:
                request = ChangeState.Request(transition=Transition(label=transition))
                ok = bool(_call(node, ChangeState, f"{full}/change_state", request, timeout).success)
            state = _call(node, GetState, f"{full}/get_state", GetState.Request(), timeout).current_state.label
        finally:
            node.destroy_node()
    return ok, state
