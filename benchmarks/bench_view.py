"""The view's cost on the loop: ``hawt launch ipc`` without and with ``--view``, lockstep and realtime.

With the view, a Foxglove WebSocket client (the ``websockets`` package, in a thread of this process)
subscribes to every channel the view advertises and counts what it receives. Lockstep: the plant's
real-time factor, simulated time over the wall time from its first step to its last ("finished N steps
(T s simulated) in W s wall"). Realtime: the plant's loop latency (measurement sent -> command of that
step received: p50, p99, max) and late steps, as its finished line reports them.

Usage: ./hawt bench view [--duration S] [--repeat N]
"""
import argparse
import asyncio
import json
import re
import subprocess
import sys
import threading
import time
from typing import Optional

import websockets

_FINISHED = re.compile(r"finished (\d+) steps \(([\d.]+) s simulated\) in ([\d.]+) s wall")
_LATENCY = re.compile(r"loop latency .*")
_SERVING = re.compile(r"serving the graph on ws://127\.0\.0\.1:(\d+)")


class Client(threading.Thread):
    """A Foxglove WebSocket client subscribed to every advertised channel, counting message frames."""

    def __init__(self, port: int) -> None:
        super().__init__(daemon=True)
        self.port = port
        self.channels = 0
        self.messages = 0
        self.stop = threading.Event()

    def run(self) -> None:
        asyncio.run(self._run())

    async def _run(self) -> None:
        async with websockets.connect(f"ws://127.0.0.1:{self.port}", subprotocols=["foxglove.sdk.v1"],
                                      max_size=None) as socket:
            while not self.stop.is_set():
                try:
                    frame = await asyncio.wait_for(socket.recv(), 0.2)
                except asyncio.TimeoutError:
                    continue
                except websockets.ConnectionClosed:
                    return  # the view stopped with the graph
                if isinstance(frame, bytes):
                    self.messages += frame[0] == 0x01
                    continue
                message = json.loads(frame)
                if message["op"] == "advertise":
                    subscriptions = [{"id": c["id"], "channelId": c["id"]} for c in message["channels"]]
                    self.channels += len(subscriptions)
                    await socket.send(json.dumps({"op": "subscribe", "subscriptions": subscriptions}))


def run(duration: float, view: bool, mode: str) -> tuple[str, Optional[Client]]:
    """One ``hawt launch ipc`` run: the plant's real-time factor (lockstep) or loop latency (realtime), and the
    view's client if any."""
    command = [sys.executable, "-m", "hawt_tools.cli", "launch", "ipc", f"duration:={duration:g}", f"mode:={mode}"]
    process = subprocess.Popen(command + (["--view", "--view-port", "0"] if view else []), stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
    client, finished, latency, lines = None, None, None, []
    for line in process.stdout:
        lines.append(line)
        serving = _SERVING.search(line)
        if serving and client is None:
            client = Client(int(serving.group(1)))
            client.start()
        finished = finished or _FINISHED.search(line)
        latency = latency or _LATENCY.search(line)
    if process.wait() != 0 or finished is None or (mode == "realtime" and latency is None):
        sys.exit(f"bench view: hawt launch ipc failed:\n{''.join(lines[-40:])}")
    if client is not None:
        client.stop.set()
        client.join(timeout=10)
    factor = float(finished.group(2)) / float(finished.group(3))
    return (f"{factor:.2f}x real time" if mode == "lockstep" else latency.group(0)), client


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=60.0, help="simulated time per run [s] (default 60)")
    parser.add_argument("--repeat", type=int, default=1, help="runs of each variant, alternating (default 1)")
    args = parser.parse_args()
    for _ in range(args.repeat):
        for mode in ("lockstep", "realtime"):
            for view in (False, True):
                start = time.monotonic()
                figure, client = run(args.duration, view, mode)
                seen = f"; client: {client.messages} messages on {client.channels} channels" if client else ""
                print(f"ipc {mode} {'with' if view else 'without'} view: {figure} ({args.duration:g} s simulated, "
                      f"launch {time.monotonic() - start:.1f} s wall){seen}", flush=True)


if __name__ == "__main__":
    main()
