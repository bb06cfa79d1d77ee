"""The studio's web app: routes only (FastAPI).

``/api/...`` is the JSON API (its OpenAPI spec at ``/openapi.json``), ``/ws`` the live
stream, ``/vendor/three/`` three.js from the repository's ``node_modules``, and ``/``
the page (``studio/web``). Every model call goes through :class:`Hub`, which runs them
in one thread, in order, and sends what they return to the pages.
"""

from __future__ import annotations

import asyncio
import os
import time
from collections import deque
from collections.abc import AsyncIterator, Callable
from concurrent.futures import ThreadPoolExecutor
from contextlib import asynccontextmanager
from pathlib import Path
from urllib.parse import urlsplit

import anyio
from fastapi import FastAPI, WebSocket, WebSocketDisconnect
from fastapi.responses import Response
from fastapi.staticfiles import StaticFiles
from starlette.middleware.trustedhost import TrustedHostMiddleware
from pydantic import BaseModel

from sketchanim.errors import InputError
from sketchanim.studio import protocol
from sketchanim.studio.handlers import error_code, handle
from sketchanim.studio.session import Session

WEB = Path(__file__).parent / "web"
#: three.js, installed by ``npm ci`` (scripts/setup) into the repository's node_modules.
THREE = Path(__file__).resolve().parents[3] / "node_modules" / "three"
#: Messages a page may send per second, and in one burst.
RATE, BURST = 300.0, 600.0


class ReadyReply(BaseModel):
    """``GET /api/ready``'s answer."""

    ready: bool


class Client:
    """One page's socket: what is waiting to go out to it, previews coalesced by key
    (a newer one replaces one not yet sent)."""

    def __init__(self, number: int, socket: WebSocket) -> None:
        self.number = number
        self.socket = socket
        self.queue: deque[dict] = deque()
        self.previews: dict[str, dict] = {}
        self.wake = asyncio.Event()
        self.tokens, self.clock = BURST, time.monotonic()

    def put(self, message: dict) -> None:
        if message.get("type") == "preview":
            self.previews.pop(message["key"], None)
            self.previews[message["key"]] = message
        else:
            self.queue.append(message)
        self.wake.set()

    def allowed(self) -> bool:
        """Take a token from the rate limit's bucket; False when it is empty."""
        now = time.monotonic()
        self.tokens = min(BURST, self.tokens + (now - self.clock) * RATE)
        self.clock = now
        if self.tokens < 1:
            return False
        self.tokens -= 1
        return True

    async def pump(self) -> None:
        """Send what is queued, in order, then the latest previews, until closed."""
        while True:
            await self.wake.wait()
            self.wake.clear()
            while self.queue or self.previews:
                if self.queue:
                    message = self.queue.popleft()
                else:
                    message = self.previews.pop(next(iter(self.previews)))
                await self.socket.send_json(message)


class Hub:
    """The session, its one model thread, and the pages connected to it."""

    def __init__(self, session: Session) -> None:
        self.session = session
        self.thread = ThreadPoolExecutor(1, thread_name_prefix="sketchanim-model")
        self.clients: dict[int, Client] = {}
        self._numbers = iter(range(1, 2**62))
        self._saving: asyncio.Task | None = None

    async def call(self, work: Callable, *args: object) -> object:
        """Run ``work(*args)`` in the model's thread, after what was queued before it."""
        return await asyncio.get_running_loop().run_in_executor(self.thread, work, *args)

    @property
    def ready(self) -> bool:
        """Whether the compiled kernels are warm (the session's ``state`` says it too)."""
        return self.session.ready

    @ready.setter
    def ready(self, ready: bool) -> None:
        self.session.ready = ready

    def send(self, out: list[protocol.Out], sender: Client | None) -> None:
        for audience, message in out:
            for client in self.clients.values():
                if audience == "all" or (audience == "others") != (client is sender):
                    client.put(message)

    async def warm(self) -> None:
        """Warm the compiled kernels (see :func:`~sketchanim.anim.warmup.warm_recorder`,
        on its own scene, in its own thread: the pages are served meanwhile), then tell
        the pages."""
        from sketchanim.anim.warmup import warm_recorder

        await asyncio.to_thread(warm_recorder)
        self.ready = True
        self.send([("all", protocol.wire(protocol.Ready()))], None)

    async def handle(self, client: Client, text: str) -> None:
        """One message from ``client``: parsed, run, answered."""
        if not client.allowed():
            client.put(protocol.wire(protocol.Error(id=None, ref=None, code="rate",
                                                    message=f"more than {RATE:.0f} messages a second; "
                                                            "this one was dropped")))
            return
        try:
            message = protocol.parse(text)
        except protocol.BadMessage as err:
            code = "too_large" if len(text) > protocol.MAX_MESSAGE_BYTES else "bad_message"
            client.put(protocol.wire(protocol.Error(id=err.id, ref=err.type, code=code, message=str(err))))
            return
        try:
            out = await self.call(handle, self.session, message, client.number)
        except InputError as err:
            code = error_code(message, err, self.session)
            client.put(protocol.wire(protocol.Error(id=message.id, ref=message.type, code=code, message=str(err))))
            return
        self.send(out, client)
        if message.id is not None:
            client.put(protocol.wire(protocol.Ack(id=message.id, ref=message.type)))
        self.autosave(0.0 if message.type == "take.end" else 0.5)

    def autosave(self, delay: float) -> None:
        """Save ``delay`` seconds from now if anything changed (one save for a burst of
        changes; after a take at once, its answer sent first)."""
        if self.session.dirty and (self._saving is None or self._saving.done()):
            async def later() -> None:
                await asyncio.sleep(delay)
                await self.call(self.session.save)
            self._saving = asyncio.get_running_loop().create_task(later())

    async def leave(self, client: Client) -> None:
        """A page went away: a take it was recording ends as if released (kept), what it
        previewed without a set goes back (:meth:`Session.leave`)."""
        self.clients.pop(client.number, None)
        out = await self.call(self.session.leave, client.number)
        self.send(out, None)
        self.autosave(0.0)


def same_origin(origin: str | None, host: str | None) -> bool:
    """Whether a websocket handshake's ``Origin`` is the server's own (no Origin: a
    script, not a page, allowed); localhost and 127.0.0.1 are one host.

    >>> same_origin("http://localhost:8000", "127.0.0.1:8000"), same_origin("http://evil.com", "127.0.0.1:8000")
    (True, False)
    """
    if origin is None:
        return True
    local = {"localhost", "127.0.0.1", "[::1]", "::1"}
    try:
        theirs, ours = urlsplit(origin), urlsplit(f"//{host or ''}")
        if theirs.scheme not in ("http", "https"):
            return False
        port = theirs.port or (443 if theirs.scheme == "https" else 80)
        mine = ours.port or 80
        same_host = theirs.hostname == ours.hostname or {theirs.hostname, ours.hostname} <= local
    except ValueError:
        return False
    return same_host and port == mine


def create_app(project: str | os.PathLike[str], *, warm: bool = True, hosts: list[str] | None = None,
               close: bool = False, read_only: bool | None = None,
               exports: str | os.PathLike[str] | None = None) -> FastAPI:
    """The studio app for the project file ``project`` (created if missing). With
    ``warm``, the compiled kernels are warmed at start and ``ready`` is said after;
    without, the app is ready at once. ``hosts``: the only ``Host`` headers answered
    (a page on another site cannot reach a local server by renaming it: DNS
    rebinding); any if None. When the app stops, a take still running is
    kept and the project saved, and with ``close`` the file is closed (a server's app;
    otherwise ``app.state.hub.session.close()`` does it, and the app can start again).
    ``read_only`` and ``exports``: as :class:`Session` takes them.

    >>> import tempfile
    >>> from fastapi.testclient import TestClient
    >>> app = create_app(Path(tempfile.mkdtemp()) / "a.sketchanim", warm=False)
    >>> with TestClient(app) as client:
    ...     ready, objects = client.get("/api/ready").json(), client.get("/api/state").json()["objects"]
    >>> ready, [o["name"] for o in objects]
    ({'ready': True}, ['box', 'ball', 'cone', 'lamp', 'cam'])
    >>> app.state.hub.session.close()
    """
    hub = Hub(Session(project, read_only, exports))

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        task = asyncio.get_running_loop().create_task(hub.warm()) if warm else None
        hub.ready = not warm
        try:
            yield
        finally:
            if task is not None:
                task.cancel()
            await hub.call(hub.session.close if close else hub.session.flush)

    app = FastAPI(title="sketchanim studio", lifespan=lifespan)
    if hosts is not None:
        app.add_middleware(TrustedHostMiddleware, allowed_hosts=hosts)
    app.state.hub = hub

    @app.get("/api/ready", response_model=ReadyReply)
    async def ready() -> ReadyReply:
        """Whether the compiled kernels are warm (the first take reduces at full speed)."""
        return ReadyReply(ready=hub.ready)

    @app.get("/api/project", response_class=Response,
             responses={200: {"content": {"application/json": {}},
                              "description": "The project as `sketchanim export PROJECT -o X.json` writes it."}})
    async def project_document() -> Response:
        """The project document, raw takes included, exactly as the export writes it."""
        return Response(await hub.call(hub.session.export_document), media_type="application/json")

    @app.get("/api/state")
    async def state() -> dict:
        """What the websocket's ``state`` message holds: objects, tracks, history."""
        return await hub.call(hub.session.state)

    @app.websocket("/ws")
    async def stream(socket: WebSocket) -> None:
        if not same_origin(socket.headers.get("origin"), socket.headers.get("host")):
            await socket.close(code=1008)           # before accept: the handshake is refused (403)
            return
        await socket.accept()
        client = Client(next(hub._numbers), socket)
        hub.clients[client.number] = client
        client.put(await hub.call(hub.session.state))
        pump = asyncio.get_running_loop().create_task(client.pump())
        try:
            while True:
                frame = await socket.receive()
                if frame["type"] == "websocket.disconnect":
                    break
                await hub.handle(client, frame.get("text") or (frame.get("bytes") or b"").decode("utf-8", "replace"))
        except WebSocketDisconnect:
            pass
        finally:
            pump.cancel()
            with anyio.CancelScope(shield=True):     # a take the page was recording is kept, even on a cancel
                await hub.leave(client)

    for url, folder, html in (("/vendor/three", THREE, False), ("/", WEB, True)):
        if folder.is_dir():                         # three.js comes with scripts/setup; the page with the package
            app.mount(url, StaticFiles(directory=folder, html=html), name=url)
    return app
