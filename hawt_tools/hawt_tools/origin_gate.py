"""The view's front door: a WebSocket relay that lets in native clients and the web pages it is told to trust,
speaking every subprotocol name current Foxglove clients offer.

A browser sends the page's ``Origin`` with every WebSocket handshake, and any page open on this
machine can reach a server on 127.0.0.1. foxglove-sdk's server (0.30) does not look at the header,
so ``hawt view`` puts this relay in front of it: the Foxglove server listens on a loopback port of
its own, and the relay listens where the user asked. A handshake with an ``Origin`` that is not in
``allowed`` is answered 403 and logged with the option that would accept it; one without the
header (a native client: the Foxglove desktop app, a script) is let in. Every frame is passed on
unchanged in both directions.

Subprotocols: foxglove-sdk's server (0.30) accepts only ``foxglove.sdk.v1`` and ``foxglove.sdk.v1.1``
and answers anything else with a bare 400 ("Missing expected sec-websocket-protocol header"),
logging only "handshake failed". Clients older than the SDK (the Foxglove app before it, older
Lichtblick, roslibjs-foxglove 0.0.4) offer ``foxglove.websocket.v1``, the name of the same protocol
before the SDK renamed it (foxglove/ws-protocol ``docs/spec.md``; Foxglove's discussion 1131: the
rename changed no message). The gate accepts all three (`SUBPROTOCOLS`, the first the client offers in that order) and asks the
server for the SDK's name of the same protocol. A client that offers none of them is answered 400
with the list, and the refusal is logged with what it offered and the list, once per offer (a client
app retries every few seconds).

Advertising: foxglove-sdk (0.30, ``ConnectedClient::advertise_channels``) queues a new channel's
advertisement to each client before it adds the channel to the ones that client may subscribe to, and
the Python channel constructor releases the GIL meanwhile; a client that answered at once was refused
"Unknown channel ID" and got nothing on that channel (5 times in 6 on this machine for a client connected
while a view started beside a running graph). The gate holds every frame from a client while the
server's owner holds ``advertising`` (the view does while it creates a channel), so a subscription
reaches the server only once the channel it names can take it.

The relay is the ``websockets`` library's server and client (its ``process_request`` hook checks the
Origin, its ``select_subprotocol`` hook the subprotocol); what is written here is only the pairing of
the two connections.
"""
from __future__ import annotations

import asyncio
import threading
from http import HTTPStatus
from types import MappingProxyType
from typing import Callable, Iterable, Optional, Sequence

from websockets.asyncio.client import connect
from websockets.asyncio.server import ServerConnection, serve
from websockets.exceptions import ConnectionClosed, InvalidHandshake, NegotiationError
from websockets.frames import CloseCode
from websockets.http11 import Request, Response
from websockets.typing import Subprotocol

__all__ = ["OriginGate", "SUBPROTOCOLS"]

SUBPROTOCOLS = MappingProxyType({
    "foxglove.sdk.v1.1": "foxglove.sdk.v1.1",
    "foxglove.sdk.v1": "foxglove.sdk.v1",
    "foxglove.websocket.v1": "foxglove.sdk.v1",
})
"""The WebSocket subprotocols a client may speak through the gate, in the order of preference, each with the one
the gate asks of the Foxglove server behind it (``foxglove.websocket.v1`` is the same protocol's name before
foxglove-sdk)."""


class OriginGate:
    """Relay ``host:port`` to the WebSocket server at ``backend`` (``ws://127.0.0.1:N``), refusing foreign Origins.

    Parameters
    ----------
    host, port : str, int
        Where the gate listens (port 0: any free one; :attr:`port` is the one taken).
    backend : str
        URL of the server behind the gate.
    allowed : iterable of str
        Origins let in besides clients that send none (e.g. ``https://app.foxglove.dev``).
    log : callable
        Takes one line per refused client.
    advertising : threading.Lock
        Held while the server creates a channel; frames from clients wait for it.

    Raises
    ------
    OSError
        The port cannot be taken (in use, or not allowed).
    """

    def __init__(self, host: str, port: int, backend: str, allowed: Iterable[str],
                 log: Callable[[str], None], advertising: threading.Lock) -> None:
        self.backend = backend
        self.allowed = frozenset(allowed)
        self.log = log
        self.advertising = advertising
        self._refused_offers: set[tuple[str, ...]] = set()
        self.port: Optional[int] = None
        self._loop = asyncio.new_event_loop()
        self._stopped: Optional[asyncio.Event] = None
        started = threading.Event()
        failure: list[BaseException] = []
        self._thread = threading.Thread(target=self._run, args=(host, port, started, failure), daemon=True,
                                        name="origin_gate")
        self._thread.start()
        started.wait()
        if failure:
            raise failure[0]

    def _run(self, host: str, port: int, started: threading.Event, failure: list) -> None:
        asyncio.set_event_loop(self._loop)
        self._loop.run_until_complete(self._serve(host, port, started, failure))
        self._loop.close()

    async def _serve(self, host: str, port: int, started: threading.Event, failure: list) -> None:
        self._stopped = asyncio.Event()
        try:
            server = await serve(self._relay, host, port, process_request=self._check_origin,
                                 select_subprotocol=self._select_subprotocol, max_size=None, compression=None)
        except OSError as error:
            failure.append(error)
            started.set()
            return
        self.port = server.sockets[0].getsockname()[1]
        started.set()
        async with server:
            await self._stopped.wait()

    def _check_origin(self, connection: ServerConnection, request: Request) -> Optional[Response]:
        origin = request.headers.get("Origin")
        if origin is None or origin in self.allowed:
            return None
        self.log(f"refused a WebSocket client from Origin {origin} (a web page; only native clients and "
                 f"--allow-origin ORIGIN are let in): hawt view --allow-origin {origin} accepts it")
        return connection.respond(HTTPStatus.FORBIDDEN, f"Origin {origin} is not allowed\n")

    def _select_subprotocol(self, connection: ServerConnection,
                            offered: Sequence[Subprotocol]) -> Subprotocol:
        """The first of `SUBPROTOCOLS` the client offers; none is NegotiationError (400 with the list), logged the
        first time that offer comes."""
        chosen = next((Subprotocol(name) for name in SUBPROTOCOLS if name in offered), None)
        if chosen is None:
            accepted = ", ".join(SUBPROTOCOLS)
            if tuple(offered) not in self._refused_offers:
                self._refused_offers.add(tuple(offered))
                self.log(f"refused a WebSocket client offering {', '.join(offered) or 'no subprotocol'}: the "
                         f"Foxglove WebSocket protocol is spoken as {accepted} (this offer is not logged again)")
            raise NegotiationError(f"unsupported subprotocol {', '.join(offered) or '(none)'}; expected one of "
                                   f"{accepted}")
        return chosen

    async def _relay(self, client: ServerConnection) -> None:
        try:
            server = await connect(self.backend, subprotocols=[Subprotocol(SUBPROTOCOLS[client.subprotocol])],
                                   max_size=None, compression=None)
        except (OSError, InvalidHandshake) as error:
            self.log(f"dropped a WebSocket client: the Foxglove server refused it ({error})")
            await client.close(CloseCode.INTERNAL_ERROR, "the Foxglove server refused the connection")
            return
        async with server:
            pumps = [asyncio.create_task(self._pump(client, server, self._after_advertising)),
                     asyncio.create_task(self._pump(server, client))]
            _, pending = await asyncio.wait(pumps, return_when=asyncio.FIRST_COMPLETED)
            for pump in pending:
                pump.cancel()

    def _after_advertising(self) -> None:
        """Return once no channel is being created (at once nearly always; else after that one, milliseconds)."""
        with self.advertising:
            pass

    @staticmethod
    async def _pump(source, sink, before: Callable[[], None] = lambda: None) -> None:
        try:
            async for frame in source:
                before()
                await sink.send(frame)
        except ConnectionClosed:
            pass

    def stop(self) -> None:
        """Close the listening socket and every relayed connection."""
        if self._stopped is not None and self._loop.is_running():
            self._loop.call_soon_threadsafe(self._stopped.set)
        self._thread.join(timeout=5.0)
