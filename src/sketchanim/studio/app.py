"""The studio's web app: routes only (FastAPI).

``/api/...`` is the JSON API (its OpenAPI spec at ``/openapi.json``), ``/ws`` the live
stream, ``/vendor/three/`` three.js from the repository's ``node_modules``, and ``/``
the page (``studio/web``). Every model call goes through :class:`Hub`, which runs them
in one thread, in order, and sends what they return to the pages.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import os
import time
from collections import deque
from collections.abc import AsyncIterator, Awaitable, Callable
from typing import Annotated
from concurrent.futures import ThreadPoolExecutor
from contextlib import asynccontextmanager
from pathlib import Path
from urllib.parse import urlsplit

import anyio
from fastapi import FastAPI, HTTPException, Query, Request, WebSocket, WebSocketDisconnect
from fastapi.responses import FileResponse, Response
from fastapi.routing import APIRoute
from fastapi.staticfiles import StaticFiles
from starlette.middleware.trustedhost import TrustedHostMiddleware
from pydantic import BaseModel, ValidationError

from sketchanim.errors import ArgumentError, InputError, StorageError
from sketchanim.export.scene_bvh import NoSkeleton
from sketchanim.project.recent import recent, remember
from sketchanim.studio import clips, downloads, projectfiles, protocol
from sketchanim.studio.exports import ExportExists
from sketchanim.studio.handlers import check_writable, error_code, handle
from sketchanim.studio.session import Session
from sketchanim.studio.sounds import SoundTooLarge, http_status, read_capped, sound_name, too_large

WEB = Path(__file__).parent / "web"
#: three.js, installed by ``npm ci`` (scripts/setup) into the repository's node_modules.
THREE = Path(__file__).resolve().parents[3] / "node_modules" / "three"
#: Messages a page may send per second, and in one burst.
RATE, BURST = 300.0, 600.0
#: Most characters of JSON waiting to go out to one page (a ``state`` of a big project is a
#: few MB; past this the backlog is dropped for a fresh state).
MAX_QUEUED = 4 * 2**20
#: Seconds a send to a page may be blocked (the page reads nothing) before its socket is closed.
SEND_TIMEOUT = 30.0
#: Seconds between the session's ticks (a silent take's end, saves and their retries).
TICK = 0.25

log = logging.getLogger("sketchanim.studio")


class ReadyReply(BaseModel):
    """``GET /api/ready``'s answer."""

    ready: bool


class Client:
    """One page's socket and what is waiting to go out to it, in order; previews
    coalesced by key (a newer one replaces one not yet sent).

    What waits is bounded by :data:`MAX_QUEUED` characters of JSON (each message is
    serialised once, when queued, and measured then): a page that does not read cannot
    grow the server. Past the bound the backlog is dropped and, once the socket takes a
    message again, the page gets one fresh ``state`` (from ``fresh``) instead, then what
    came after it. A send blocked for :data:`SEND_TIMEOUT` seconds ends the pump (the
    page is gone or hostile; the app then closes its socket).
    """

    def __init__(self, number: int, socket: WebSocket, fresh: Callable[[], Awaitable[dict]]) -> None:
        self.number = number
        self.socket = socket
        self.fresh = fresh
        self.queue: deque[str] = deque()
        self.previews: dict[str, str] = {}
        #: characters of JSON queued (``queue`` and ``previews``)
        self.queued = 0
        #: the backlog was dropped: the next message sent is a fresh ``state``
        self.stale = False
        self.wake = asyncio.Event()
        self.tokens, self.clock = BURST, time.monotonic()

    def put(self, message: dict, text: str | None = None) -> None:
        """Queue ``message`` (``text``: it as JSON, if the caller has it already)."""
        if self.stale:                  # the state the page will get is fetched later: it holds this
            return
        text = encode(message) if text is None else text
        replaced = self.previews.pop(message["key"], None) if message.get("type") == "preview" else None
        self.queued -= 0 if replaced is None else len(replaced)
        if self.queued + len(text) > MAX_QUEUED and (self.queue or self.previews):
            log.warning("page %d is not reading: %d characters of messages dropped, it gets a fresh state "
                        "when it reads again", self.number, self.queued + len(text))
            self.queue.clear()
            self.previews.clear()
            self.queued, self.stale = 0, True
        elif message.get("type") == "preview":
            self.previews[message["key"]] = text
            self.queued += len(text)
        else:
            self.queue.append(text)
            self.queued += len(text)
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

    def _next(self) -> str:
        text = self.queue.popleft() if self.queue else self.previews.pop(next(iter(self.previews)))
        self.queued -= len(text)
        return text

    async def _send(self, text: str) -> bool:
        """Send ``text``; False if the page went away (the reader sees it too)."""
        try:
            await asyncio.wait_for(self.socket.send_text(text), SEND_TIMEOUT)
        except TimeoutError:
            raise Unread(f"page {self.number} has read nothing for {SEND_TIMEOUT:g} s") from None
        except (WebSocketDisconnect, OSError, RuntimeError):    # gone, or closed: starlette's RuntimeError
            return False
        return True

    async def pump(self) -> None:
        """Send what is queued, in order, then the latest previews, until the page goes
        away (returns) or stops reading (:class:`Unread`)."""
        while True:
            await self.wake.wait()
            self.wake.clear()
            while self.stale or self.queue or self.previews:
                if self.stale:
                    state = await self.fresh()          # after every model call whose messages were dropped
                    self.queue.clear()                  # put meanwhile: older than the state (or not model news)
                    self.previews.clear()
                    self.queued, self.stale = 0, False
                    text = encode(state)
                else:
                    text = self._next()
                if not await self._send(text):
                    return


class Unread(Exception):
    """A page's socket took no message for :data:`SEND_TIMEOUT` seconds."""


def encode(message: dict) -> str:
    """``message`` as its websocket text frame (JSON, as starlette's ``send_json`` writes it).

    >>> encode({"type": "ack", "id": 1, "ref": "ping"})
    '{"type":"ack","id":1,"ref":"ping"}'
    """
    return json.dumps(message, separators=(",", ":"), ensure_ascii=False)


def error(code: protocol.ErrorCode, text: str, id: object = None, ref: str | None = None) -> dict:
    """An ``error`` reply: ``id`` only if it is a valid id, the text cut to
    :data:`~.protocol.MAX_ERROR_TEXT` characters.

    >>> error("failed", "x" * 400, id="y" * 100)["id"], len(error("failed", "x" * 400)["message"])
    (None, 300)
    """
    return protocol.wire(protocol.Error(id=protocol.readable_id(id), ref=ref, code=code, message=protocol.short(text)))


class Hub:
    """The session, its one model thread, and the pages connected to it."""

    def __init__(self, session: Session) -> None:
        self.session = session
        self.thread = ThreadPoolExecutor(1, thread_name_prefix="sketchanim-model")
        #: Where tracks are reduced again from their takes (``track.reduce``), one at a time.
        self.reductions = ThreadPoolExecutor(1, thread_name_prefix="sketchanim-reductions")
        self._reducing: set[asyncio.Task] = set()
        self.clients: dict[int, Client] = {}
        self._numbers = iter(range(1, 2**62))

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

    def client(self, socket: WebSocket) -> Client:
        """A new page on ``socket``, among the connected (its first ``state`` is the caller's to queue)."""
        client = Client(next(self._numbers), socket, lambda: self.call(lambda: self.session.state()))
        self.clients[client.number] = client
        return client

    def send(self, out: list[protocol.Out], sender: Client | None) -> None:
        """Queue each message for its audience (serialised once for all of them)."""
        for audience, message in out:
            text = None
            for client in list(self.clients.values()):
                if audience == "all" or (audience == "others") != (client is sender):
                    text = encode(message) if text is None else text
                    client.put(message, text)

    async def warm(self) -> None:
        """Warm the compiled kernels (see :func:`~sketchanim.anim.warmup.warm_recorder`,
        on its own scene, in its own thread: the pages are served meanwhile), then tell
        the pages."""
        from sketchanim.anim.warmup import warm_recorder

        await asyncio.to_thread(warm_recorder)
        self.ready = True
        self.send([("all", protocol.wire(protocol.Ready()))], None)

    async def tick(self) -> None:
        """What time does, every :data:`TICK` seconds until cancelled: the session's
        :meth:`~.session.Session.tick` (a silent take ends, what changed is saved, a
        failed save is tried again) in the model thread, its messages sent."""
        while True:
            try:
                now = time.monotonic()
                self.send(await self.call(lambda: self.session.tick(now)), None)
            except Exception:                       # a bug: logged, and time goes on
                log.exception("the studio's timer failed")
            await asyncio.sleep(TICK)

    async def save(self) -> None:
        """Save now (in the model thread) and send what the save says."""
        self.send(await self.call(lambda: self.session.save()), None)

    async def handle(self, client: Client, frame: str | bytes) -> None:
        """One frame from ``client``: parsed, run, answered (an error reply for anything
        refused; the socket stays open)."""
        now = time.monotonic()
        self.thread.submit(lambda: self.session.heard(client.number, now))    # in order with the model's calls
        if not client.allowed():
            client.put(error("rate", f"more than {RATE:.0f} messages a second; this one was dropped"))
            return
        try:
            message = protocol.parse(frame)
        except protocol.BadMessage as err:
            client.put(error(err.code, str(err), err.id, err.type))
            return
        if message.type in ("track.reduce", "track.samples", "sound.beats"):  # in their own thread, the model's goes on
            work = {"track.reduce": self.reduce, "track.samples": self.kept_samples, "sound.beats": self.beats}[message.type]
            task = asyncio.create_task(self.carry_out(client, message, lambda: work(message)))
            self._reducing.add(task)
            task.add_done_callback(self._reducing.discard)
            return
        await self.carry_out(client, message, lambda: self.call(lambda: handle(self.session, message, client.number)))

    async def reduce(self, message: protocol.TrackReduce) -> list[protocol.Out]:
        """A ``track.reduce``: checked and put in the model's thread, the tracks reduced
        again from their takes in the reductions' thread (the model's serves the other
        messages meanwhile; a track changed meanwhile is refused when put, and all of it
        when another project was opened meanwhile)."""
        session = self.session
        check_writable(session, message)
        work = await self.call(session.reduction, message.paths, message.tol)
        made = await asyncio.get_running_loop().run_in_executor(self.reductions, work)

        def put() -> list[protocol.Out]:
            if self.session is not session:
                raise ArgumentError("track.reduce", "another project was opened meanwhile; nothing was changed")
            return session.reduced(made, message.preview)

        return await self.call(put)

    async def kept_samples(self, message: protocol.TrackSamples) -> list[protocol.Out]:
        """A ``track.samples``: the track taken in the model's thread, the samples its
        curve keeps found in the reductions' thread."""
        work = await self.call(lambda: self.session.kept_samples(message.path))
        return await asyncio.get_running_loop().run_in_executor(self.reductions, work)

    async def beats(self, message: protocol.SoundBeats) -> list[protocol.Out]:
        """A ``sound.beats``: checked in the model's thread, the sound's onsets found in the
        reductions' thread (seconds of audio analysis), the event track put in the model's."""
        check_writable(self.session, message)
        work = await self.call(self.session.beat_finding, message.name, message.path)
        found = await asyncio.get_running_loop().run_in_executor(self.reductions, work)
        return await self.call(self.session.beats_found, found)

    async def carry_out(self, client: Client, message: protocol.Message,
                        run: Callable[[], Awaitable[list[protocol.Out]]]) -> None:
        """Run ``message`` (``run`` does), send what it says and its ``ack``, or an error
        reply for anything refused (the socket stays open)."""
        try:
            out = await run()
        except InputError as err:
            client.put(error(error_code(message, err, self.session), str(err), message.id, message.type))
            return
        except Exception as err:                    # a bug of the server's, not the page's: logged with its traceback
            log.exception("%s from page %d failed", message.type, client.number)
            client.put(error("failed", f"the server failed to carry out {message.type} "
                                       f"({type(err).__name__}); see the server's log", message.id, message.type))
            return
        self.send(out, client)
        if message.id is not None:
            client.put(protocol.wire(protocol.Ack(id=message.id, ref=message.type)))
        if message.type in ("take.end", "take.cancel"):
            await self.save()                       # a take's end is on disk at once

    async def read(self, client: Client) -> None:
        """Handle ``client``'s frames until its page goes away."""
        while True:
            frame = await client.socket.receive()
            if frame["type"] == "websocket.disconnect":
                return
            data = frame.get("text")
            await self.handle(client, data if data is not None else frame.get("bytes") or b"")

    async def leave(self, client: Client) -> None:
        """A page went away: a take it was recording ends as if released (kept, and
        saved at once), what it previewed without a set goes back
        (:meth:`Session.leave`)."""
        self.clients.pop(client.number, None)
        self.send(await self.call(lambda: self.session.leave(client.number)), None)
        await self.save()

    async def serve(self, socket: WebSocket) -> None:
        """A page's socket, accepted: its first ``state``, then its frames and what goes
        out to it, until it goes away or reads nothing for :data:`SEND_TIMEOUT` seconds
        (then closed, code 1008)."""
        client = self.client(socket)
        reader = pump = None
        try:
            client.put(await self.call(lambda: self.session.state()))
            reader = asyncio.ensure_future(self.read(client))
            pump = asyncio.ensure_future(client.pump())
            await asyncio.wait((reader, pump), return_when=asyncio.FIRST_COMPLETED)
            if pump.done() and isinstance(pump.exception(), Unread):
                log.warning("%s: its socket is closed", pump.exception())
                with contextlib.suppress(Exception):          # the close frame may not get through either
                    await asyncio.wait_for(socket.close(code=1008), 1.0)
            else:
                if pump.done() and pump.exception() is None:  # gone: what it sent before it went is still handled
                    await reader
                for task in (reader, pump):
                    if task.done() and task.exception() is not None:
                        raise task.exception()
        except WebSocketDisconnect:
            pass
        finally:
            for task in (reader, pump):
                if task is not None:
                    task.cancel()
            with anyio.CancelScope(shield=True):     # a take the page was recording is kept, even on a cancel
                await self.leave(client)

    # -- files: save as, open (projectfiles.py) ------------------------------------------------

    #: The folder the page saves copies into and opens projects from (set by create_app).
    files: Path
    #: How the studio was started: ``read_only`` and ``exports`` for each project it opens.
    opening: tuple[bool | None, str | os.PathLike[str] | None] = (None, None)

    async def switch(self, path: Path) -> None:
        """Go on with the project at ``path``: the open one saved and closed (its lock
        let go), ``path`` opened (as the studio was started: read-only or not, its exports
        folder) and remembered in the recent list, every page sent its ``state``. Refused
        (an :class:`InputError`, nothing changed) while a take records or a reduction
        runs, or when ``path`` does not open (it is locked, damaged...)."""
        if self._reducing:
            raise ArgumentError("project", "tracks are being reduced again; open the project once they are back")
        old = self.session
        if path.resolve() == old.path:
            raise AlreadyOpen("project", f"{old.path.name} is the open project")

        def reopen() -> Session:
            if old.take is not None:
                raise ArgumentError("project", "a take is recording; end it before another project opens")
            try:
                new = Session(path, *self.opening)  # fails before anything changed: the open project stays
            except OSError as err:
                raise StorageError(f"{path.name}: cannot be opened ({err.strerror or err})") from None
            old.close()
            self.session = new                  # in the model's thread: what comes after it runs on the new one
            return new

        new = await self.call(reopen)
        remember_opened(new.path)
        state = await self.call(new.state)
        for client in list(self.clients.values()):
            client.put(state)


class AlreadyOpen(ArgumentError):
    """The project to open is the open one."""


def refusal_status(err: InputError) -> int:
    """The HTTP status of a refused save as or open: 409 for a name taken or the open
    project, 404 for a project not there, else 400.

    >>> refusal_status(AlreadyOpen("project", "a.sketchanim is the open project"))
    409
    """
    if isinstance(err, (ExportExists, AlreadyOpen)):
        return 409
    return 404 if isinstance(err, projectfiles.ProjectMissing) else 400


def remember_opened(path: Path) -> None:
    """Put ``path`` first in the recent list; a list that cannot be written is logged."""
    try:
        remember(path)
    except OSError as err:
        log.warning("the recent projects' list cannot be written (%s): %s", err.filename, err.strerror or err)


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
               exports: str | os.PathLike[str] | None = None,
               files: str | os.PathLike[str] | None = None) -> FastAPI:
    """The studio app for the project file ``project`` (created if missing). With
    ``warm``, the compiled kernels are warmed at start and ``ready`` is said after;
    without, the app is ready at once. ``hosts``: the only ``Host`` headers answered
    (a page on another site cannot reach a local server by renaming it: DNS
    rebinding); any if None. When the app stops, a take still running is
    kept and the project saved, and with ``close`` the file is closed (a server's app;
    otherwise ``app.state.hub.session.close()`` does it, and the app can start again).
    ``read_only`` and ``exports``: as :class:`Session` takes them. ``files``: the folder
    the page saves copies into and opens projects from (the project's if None); a
    project opened from the page is put first in the recent list
    (:mod:`sketchanim.project.recent`; ``sketchanim studio`` puts its own there).

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
    hub.opening = (read_only, exports)
    hub.files = hub.session.folder if files is None else Path(files).resolve()
    if not hub.files.is_dir():
        hub.session.close()
        raise ArgumentError("files", f"{hub.files} is not a folder")

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        loop = asyncio.get_running_loop()
        tasks = [loop.create_task(hub.tick())] + ([loop.create_task(hub.warm())] if warm else [])
        hub.ready = not warm
        try:
            yield
        finally:
            tasks += hub._reducing                  # a reduction in flight is dropped (it changed nothing yet)
            for task in tasks:
                task.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)
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

    @app.post("/api/sounds", response_model=protocol.SoundInfo,
              responses={code: {"description": why} for code, why in (
                  (400, "not a name a sound may have"), (403, "the project is open read-only"),
                  (409, "the project has a sound of that name (import with overwrite)"),
                  (413, "larger than the studio imports"), (415, "not audio the studio can decode"),
                  (507, "the sounds folder cannot be written"))})
    async def import_sound(request: Request, name: str, overwrite: bool = False) -> protocol.SoundInfo:
        """Import the request's body (an audio file) as the sound ``name``: stored in the
        project's sounds folder, listed by the project; refused with nothing changed."""
        session = hub.session
        try:
            if session.read_only:
                raise HTTPException(403, f"{session.path.name} is open read-only: sounds cannot be imported")
            sound_name(name, session.path)
            limit = session.sounds.limit
            length = request.headers.get("content-length", "")
            if length.isdigit() and int(length) > limit:
                raise SoundTooLarge(too_large(name, limit))
            data = await read_capped(request.stream(), name, limit)
            sound = await asyncio.to_thread(session.sounds.stored, name, data, overwrite)
        except InputError as err:
            raise HTTPException(http_status(err), str(err)) from None
        hub.send(await hub.call(session.add_sound, sound), None)
        return await hub.call(session.sound_info, name)

    @app.get("/api/sounds", response_model=list[protocol.SoundInfo])
    async def sounds() -> list[protocol.SoundInfo]:
        """The project's sounds (as ``state.sounds``)."""
        return await hub.call(hub.session.sound_infos)

    @app.api_route("/api/sounds", methods=["PUT", "PATCH", "DELETE", "OPTIONS"], include_in_schema=False)
    async def sounds_other() -> Response:
        """Not a method of ``/api/sounds`` (answered here, not by the page's static files)."""
        return Response(status_code=405, headers={"Allow": "GET, HEAD, POST"})

    @app.get("/api/sounds/{name}", response_class=FileResponse,
             responses={200: {"content": {"audio/*": {}}, "description": "the sound's file"},
                        404: {"description": "no such sound, or its file is missing"}})
    async def sound_file(name: str) -> FileResponse:
        """The file of the sound ``name`` (ranges served, for the page's audio element)."""
        try:
            path = await hub.call(hub.session.sounds.path, name)
        except InputError as err:
            raise HTTPException(http_status(err), str(err)) from None
        return FileResponse(path)

    @app.get("/api/export/choices", response_model=downloads.ExportChoices)
    async def export_choices() -> downloads.ExportChoices:
        """What the export dialog offers: each format, its file, what each client plays from it."""
        s = hub.session
        return await hub.call(lambda: downloads.choices(s.path, s.scene, dict(s.player.tracks)))

    @app.get("/api/export", response_class=Response,
             responses={200: {"content": {"model/gltf-binary": {}, "application/octet-stream": {},
                                          "application/json": {}},
                              "description": "The export, as a download named after the project."},
                        400: {"description": "Not an export format, or one this server cannot write."},
                        409: {"description": "BVH of a scene without a skeleton (import a clip first)."}})
    async def export_download(format: Annotated[str, Query(json_schema_extra={"enum": list(downloads.FORMATS)})]
                              = "glb") -> Response:
        """The scene (``glb``, ``glb-frames``, ``usd``, ``bvh``) or the project (``json``) as a
        download, made by the writers ``sketchanim export`` uses; nothing is written."""
        s = hub.session
        try:
            fmt = downloads.check_format(format)
            data = await hub.call(lambda: downloads.build(format, s.path, s.scene, dict(s.player.tracks), s.fps,
                                                          s.export_document))
        except NoSkeleton as err:
            raise HTTPException(409, str(err)) from None
        except InputError as err:
            raise HTTPException(400, str(err)) from None
        return Response(data, media_type=fmt.media_type,
                        headers={"Content-Disposition": downloads.disposition(downloads.file_name(s.path, fmt))})

    @app.post("/api/project/save-as", response_model=projectfiles.ProjectFile,
              responses={400: {"description": "Not a project name, or not writable; nothing changed."},
                         409: {"description": "The name is taken; nothing changed."}})
    async def save_as(name: Annotated[str, Query(json_schema_extra={"pattern": projectfiles.NAME_PATTERN})]
                      ) -> projectfiles.ProjectFile:
        """Write the model, as the pages see it, as a new project ``name`` in the files
        folder (atomically, never over a file), then go on with the copy: every page
        gets its ``state``; the project it was is saved and closed as it is."""
        try:
            target = projectfiles.copy_target(hub.files, name)
            s = hub.session
            await hub.call(lambda: projectfiles.write_copy(target, s.scene, s.player.tracks, s.tolerances, s.fps))
            await hub.switch(target)
        except InputError as err:
            raise HTTPException(refusal_status(err), str(err)) from None
        return projectfiles.ProjectFile(path=str(target), name=target.name, exists=True)

    @app.post("/api/project/open", response_model=projectfiles.ProjectFile,
              responses={400: {"description": "Not a project the page may open, or it does not open; nothing changed."},
                         404: {"description": "No such project file."},
                         409: {"description": "It is the open project; nothing changed."}})
    async def open_project(path: str) -> projectfiles.ProjectFile:
        """Go on with another project: a bare name in the files folder, or a path of
        the recent list; the open one is saved and closed, every page gets its ``state``."""
        try:
            target = projectfiles.openable(path, hub.files, recent())
            await hub.switch(target)
        except InputError as err:
            raise HTTPException(refusal_status(err), str(err)) from None
        return projectfiles.ProjectFile(path=str(target), name=target.name, exists=True)

    @app.get("/api/recent", response_model=projectfiles.ProjectFiles)
    async def recent_projects() -> projectfiles.ProjectFiles:
        """The open project, the files folder, and the projects opened lately (newest first)."""
        return projectfiles.listing(hub.session.path, hub.files, recent())

    @app.post("/api/clips", response_model=clips.ClipImported,
              openapi_extra={"requestBody": {"required": True, "description": "The file's bytes.",
                                             "content": {"application/octet-stream": {
                                                 "schema": {"type": "string", "format": "binary"}}}}},
              responses={400: {"description": "Not a clip file, or malformed (the line and field named); nothing changed."},
                         413: {"description": "Over the upload's size limit; nothing changed."}})
    async def import_clip(request: Request,
                          name: Annotated[str, Query(json_schema_extra={"pattern": clips.NAME_PATTERN})]
                          ) -> clips.ClipImported:
        """A motion clip (the raw bytes of a .bvh) into the scene: each joint an object
        with its world position and orientation tracks; or a .c3d's markers, each an
        object with its world position track; one History step. Read and reduced in the
        reductions' thread (the model serves the pages meanwhile)."""
        try:
            data = await clip_body(request, name, clips.CLIP_UPLOADS)
        except clips.TooLarge as err:
            raise HTTPException(413, str(err)) from None
        except InputError as err:
            raise HTTPException(400, str(err)) from None
        return await add_clip(name, data, None)

    async def clip_body(request: Request, name: str, kinds: tuple[str, ...]) -> bytes:
        """An upload's body, refused (by name and size) as soon as it shows it is not one."""
        declared = request.headers.get("content-length")
        clips.check_upload(name, int(declared) if declared and declared.isdigit() else None, kinds)
        data = bytearray()
        async for chunk in request.stream():
            data += chunk
            clips.check_upload(name, len(data), kinds)
        return bytes(data)

    async def add_clip(name: str, data: bytes, skeleton: tuple[str, bytes] | None) -> clips.ClipImported:
        """Read and reduce an upload in the reductions' thread, add it as one step, tell the pages."""
        loop = asyncio.get_running_loop()
        try:
            upload = await loop.run_in_executor(hub.reductions, clips.read_upload, name, data, skeleton)
            made = await loop.run_in_executor(hub.reductions, clips.scene_clip, upload)
            names, out = await hub.call(hub.session.import_clip, Path(name).stem, made.tracks,
                                        made.parents, f"import {name}")
        except InputError as err:
            raise HTTPException(400, str(err)) from None
        hub.send(out, None)
        return clips.ClipImported(objects=names, tracks=sum(len(t) for t in made.tracks.values()),
                                  frames=len(made.times), seconds=float(made.times[-1] - made.times[0]))

    @app.post("/api/clips/amc", response_model=clips.ClipImported,
              openapi_extra={"requestBody": {"required": True, "description": "The two files' texts.",
                                             "content": {"application/json": {
                                                 "schema": clips.AmcUpload.model_json_schema()}}}},
              responses={400: {"description": "Not an ASF/AMC pair, or malformed (the file, line and field named); nothing changed."},
                         413: {"description": "Over the upload's size limit; nothing changed."}})
    async def import_amc(request: Request,
                         name: Annotated[str, Query(json_schema_extra={"pattern": clips.AMC_PATTERN})],
                         skeleton: Annotated[str, Query(json_schema_extra={"pattern": clips.ASF_PATTERN})]
                         ) -> clips.ClipImported:
        """A CMU clip into the scene: an AMC motion (``name``) with its ASF skeleton
        (``skeleton``), their texts in one JSON body (``{"skeleton", "motion"}``); as a
        .bvh is, one History step."""
        try:
            body = await clip_body(request, name, (".amc",))
            clips.check_upload(skeleton, None, (".asf",))
            pair = clips.AmcUpload.model_validate_json(body)
        except clips.TooLarge as err:
            raise HTTPException(413, str(err)) from None
        except InputError as err:
            raise HTTPException(400, str(err)) from None
        except ValidationError as err:
            raise HTTPException(400, f"{name}: the body is not {{\"skeleton\", \"motion\"}} texts "
                                     f"({err.error_count()} errors)") from None
        return await add_clip(name, pair.motion.encode(), (skeleton, pair.skeleton.encode()))

    @app.websocket("/ws")
    async def stream(socket: WebSocket) -> None:
        if not same_origin(socket.headers.get("origin"), socket.headers.get("host")):
            await socket.close(code=1008)           # before accept: the handshake is refused (403)
            return
        await socket.accept()
        await hub.serve(socket)

    # the last of the API's routes (any added after it would never be reached)
    @app.api_route("/api/{rest:path}", methods=["GET", "HEAD", "POST", "PUT", "PATCH", "DELETE", "OPTIONS"],
                   include_in_schema=False)
    async def methods_allowed(rest: str) -> Response:
        """A request on the API no route above takes: 405 with the methods its path takes
        (else the page's static files would answer it), 404 for no such path."""
        methods = sorted({m for r in app.routes if isinstance(r, APIRoute) and r.path == f"/api/{rest}"
                          for m in r.methods})
        return Response(status_code=405 if methods else 404, headers={"Allow": ", ".join(methods)})

    for url, folder, html in (("/vendor/three", THREE, False), ("/", WEB, True)):
        if folder.is_dir():                         # three.js comes with scripts/setup; the page with the package
            app.mount(url, StaticFiles(directory=folder, html=html), name=url)
    return app
