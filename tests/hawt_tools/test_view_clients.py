"""A standalone `hawt view` started beside a running graph: a client connected while it starts, and clients on every
Foxglove subprotocol joining after the latched messages were published, get those and the running loop on every
channel they subscribe to; a client offering no subprotocol the view speaks is refused with the reason, in its
answer and in the view's log."""
import asyncio
import json
import signal
import socket
import struct
import subprocess
import threading
import time
from collections import Counter
from typing import Callable, List

import pytest
import websockets
from launched_graph import CLI, LaunchedGraph
from mcap.records import Schema
from mcap_ros2.decoder import DecoderFactory

from hawt_tools.origin_gate import SUBPROTOCOLS

pytestmark = pytest.mark.ros

_NAMESPACE = "joined"
_MESSAGE_DATA = 0x01
_WANTED = {f"/{_NAMESPACE}/{topic}": least for topic, least in [
    ("plant/description", 1), ("controller_manager/controllers", 4), ("plant/blade_loads", 50),
    ("control/collective", 50), ("control/pitch_command", 50)]}
"""Topics a client must receive on, with how many messages at least: the latched description and the four ipc
controllers' states (published before the client joined), and three loop topics."""


class StandaloneView:
    """``hawt view --port PORT`` in a child process, its output read as it comes; stopped with SIGINT."""

    def __init__(self, port: int) -> None:
        self.port = port
        self.process = subprocess.Popen([*CLI, "view", "--port", str(port)], stdout=subprocess.PIPE,
                                        stderr=subprocess.STDOUT, text=True)
        self.lines: List[str] = []
        self._reader = threading.Thread(target=lambda: self.lines.extend(self.process.stdout), daemon=True)
        self._reader.start()

    def output(self) -> str:
        return "".join(list(self.lines))

    def wait_until(self, condition: Callable[[], bool], what: str, timeout: float = 180.0) -> None:
        """Return once ``condition()`` holds; fail with the view's output after ``timeout`` s or if it ended."""
        deadline = time.monotonic() + timeout
        while not condition():
            assert self.process.poll() is None, f"the view ended before {what}:\n{self.output()[-3000:]}"
            assert time.monotonic() < deadline, f"no {what} within {timeout:g} s:\n{self.output()[-3000:]}"
            time.sleep(0.1)

    def stop(self) -> int:
        """SIGINT (killed if it has not ended 60 s later); the exit code."""
        self.process.send_signal(signal.SIGINT)
        try:
            self.process.wait(timeout=60)
        except subprocess.TimeoutExpired:
            self.process.kill()
        self._reader.join(timeout=10)
        return self.process.returncode


def _schema(channel: dict, schemas: dict) -> Schema:
    """A channel's schema: in the channel (``foxglove.sdk.v1``), or advertised once by id (``foxglove.sdk.v1.1``)."""
    if "schemaId" in channel:
        schema = schemas[channel["schemaId"]]
        return Schema(id=schema["id"], name=schema["name"], encoding=schema["encoding"], data=schema["data"].encode())
    return Schema(id=channel["id"], name=channel["schemaName"], encoding=channel["schemaEncoding"],
                  data=channel["schema"].encode())


async def _join(port: int, subprotocol: str) -> dict:
    """Connect offering ``subprotocol``, subscribe to every channel advertised, and read until each `_WANTED` topic
    has its messages: the negotiated subprotocol, the count per topic, the error statuses and the first
    description decoded."""
    seen = {"counts": Counter(), "errors": [], "description": None}
    topics, decoders, schemas = {}, {}, {}
    deadline = time.monotonic() + 180
    while True:  # the view may still be starting: nothing listens yet
        try:
            client = await websockets.connect(f"ws://127.0.0.1:{port}", subprotocols=[subprotocol], max_size=None)
            break
        except OSError:
            assert time.monotonic() < deadline, f"nothing listens on port {port} after 180 s"
            await asyncio.sleep(0.05)
    async with client:
        seen["subprotocol"] = client.subprotocol
        while any(seen["counts"][topic] < least for topic, least in _WANTED.items()):
            assert time.monotonic() < deadline, f"within 180 s only {dict(seen['counts'])}; errors {seen['errors']}"
            frame = await asyncio.wait_for(client.recv(), 180)
            if isinstance(frame, bytes):
                if frame[0] == _MESSAGE_DATA:
                    topic = topics[struct.unpack_from("<I", frame, 1)[0]]
                    seen["counts"][topic] += 1
                    if topic.endswith("plant/description") and seen["description"] is None:
                        seen["description"] = decoders[topic](frame[13:])
                continue
            message = json.loads(frame)
            if message["op"] == "status" and message["level"] >= 2:
                seen["errors"].append(message["message"])
            if message["op"] != "advertise":
                continue
            schemas.update((schema["id"], schema) for schema in message.get("schemas", ()))
            subscriptions = []
            for channel in message["channels"]:
                topics[channel["id"]] = channel["topic"]  # subscription id = channel id
                decoders[channel["topic"]] = DecoderFactory().decoder_for(channel["encoding"], _schema(channel, schemas))
                subscriptions.append({"id": channel["id"], "channelId": channel["id"]})
            await client.send(json.dumps({"op": "subscribe", "subscriptions": subscriptions}))
    return seen


def _free_port() -> int:
    with socket.socket() as holder:
        holder.bind(("127.0.0.1", 0))
        return holder.getsockname()[1]


@pytest.fixture(scope="module")
def view_beside_a_graph():
    """A realtime ipc graph running (100 steps a second, as a user watches one; lockstep would step flat out on the
    cores the view and the clients need; composed, every node in one process, a third of the CPU of separate
    processes), then a standalone view started beside it and a first client connected as soon as the view listens,
    while it creates its channels (what that client saw is ``view.first``). Every client of the tests joins after the
    description was published and forwarded to the first."""
    with LaunchedGraph(["ipc", f"namespace:={_NAMESPACE}", "mode:=realtime", "--composed", "duration:=600", "-p",
                        "plant.report_period:=1"]) as graph:
        graph.wait_for_line("t=")
        view = StandaloneView(_free_port())
        try:
            view.first = asyncio.run(_join(view.port, "foxglove.sdk.v1"))
            yield view
        finally:
            ended = view.stop()
        assert ended == 0, view.output()[-3000:]  # SIGINT: it stops cleanly


def test_a_client_connected_while_the_view_creates_its_channels_gets_every_one_it_subscribes_to(
        view_beside_a_graph):
    """foxglove-sdk advertises a channel before it takes subscriptions to it; the view's gate holds the client's
    subscription until it does, so none is refused "Unknown channel ID" (without: 5 runs in 6) and the wanted topics
    deliver."""
    assert view_beside_a_graph.first["errors"] == []


@pytest.mark.parametrize("subprotocol", list(SUBPROTOCOLS))
def test_a_late_client_on_each_subprotocol_gets_the_latched_messages_and_every_subscribed_channel(
        view_beside_a_graph, subprotocol):
    """A client offering only ``subprotocol`` (``foxglove.websocket.v1``: clients older than foxglove-sdk) is
    accepted on it; subscribed to every advertised channel, it is refused none (no "Unknown channel ID") and
    receives the description and the controllers' states published before it joined, and the loop's topics."""
    seen = asyncio.run(_join(view_beside_a_graph.port, subprotocol))
    assert seen["subprotocol"] == subprotocol
    assert seen["errors"] == []
    assert seen["description"].turbine and seen["description"].blades == 3, seen["description"]


def test_a_client_offering_no_subprotocol_the_view_speaks_is_refused_with_the_reason_and_it_is_logged(
        view_beside_a_graph):
    """An offer of ``foxglove.sdk.v2`` only, made twice as a retrying app would, is answered 400 naming the
    subprotocols the view speaks each time; the view logs the refusal once, with what was offered and that list."""
    accepted = ", ".join(SUBPROTOCOLS)

    async def offer_v2() -> None:
        async with websockets.connect(f"ws://127.0.0.1:{view_beside_a_graph.port}", subprotocols=["foxglove.sdk.v2"]):
            pass

    for _ in range(2):
        with pytest.raises(websockets.InvalidStatus) as refused:
            asyncio.run(offer_v2())
        assert refused.value.response.status_code == 400
        assert f"expected one of {accepted}" in refused.value.response.body.decode()
    line = f"refused a WebSocket client offering foxglove.sdk.v2: the Foxglove WebSocket protocol is spoken as {accepted}"
    view_beside_a_graph.wait_until(lambda: line in view_beside_a_graph.output(), "log line of the refusal")
    assert view_beside_a_graph.output().count(line) == 1
