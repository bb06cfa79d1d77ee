"""Serving the studio: the app on uvicorn, the URL printed, the page opened."""

from __future__ import annotations

import os
import socket
import sys
import threading
import webbrowser
from collections.abc import Callable
from pathlib import Path

import uvicorn

from sketchanim.studio.app import create_app, remember_opened
from sketchanim.studio.protocol import MAX_FRAME_BYTES


def has_display() -> bool:
    """Whether a browser could be shown (a desktop session, or not Linux/BSD).

    >>> isinstance(has_display(), bool)
    True
    """
    if sys.platform.startswith(("linux", "freebsd", "openbsd")):
        return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
    return True


def server_config(app: object, **options: object) -> uvicorn.Config:
    """uvicorn's settings for the studio app: frames up to
    :data:`~.protocol.MAX_FRAME_BYTES` (larger close the socket, 1009), a ping every 20 s
    (``options``: more of uvicorn's, such as ``host`` and ``port``).

    >>> server_config(object()).ws_max_size == MAX_FRAME_BYTES
    True
    """
    return uvicorn.Config(app, log_level="warning", ws_max_size=MAX_FRAME_BYTES, ws_ping_interval=20, **options)


def serve(project: Path, host: str, port: int, browser: bool, say: Callable[[str], object] = print, *,
          read_only: bool | None = None, exports: Path | None = None, files: Path | None = None) -> None:
    """Serve the studio for ``project`` on ``host:port`` until interrupted; open the page
    in a browser if ``browser`` and there is a display. ``read_only`` and ``exports``:
    as :class:`~.session.Session` takes them; ``files``: as :func:`~.app.create_app` does. The port is bound first, so a busy one
    fails here (:class:`OSError`) before anything else starts. The project is put
    first in the recent list."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    sock.bind((host, port))
    loopback = host in ("127.0.0.1", "localhost", "::1") or host.startswith("127.")
    app = create_app(project, hosts=["127.0.0.1", "localhost", "[::1]", host] if loopback else None, close=True,
                     read_only=read_only, exports=exports, files=files)
    shown = f"[{host}]" if ":" in host else host
    url = f"http://{'127.0.0.1' if host in ('0.0.0.0', '::') else shown}:{sock.getsockname()[1]}/"
    session = app.state.hub.session
    remember_opened(session.path)
    mode = " (read-only: it plays and exports, edits are refused)" if session.read_only else ""
    say(f"sketchanim studio: {session.path}{mode} at {url} (Ctrl-C stops it); exports go to {session.exports}")
    if browser and has_display():
        threading.Timer(1.0, webbrowser.open, (url,)).start()
    uvicorn.Server(server_config(app)).run(sockets=[sock])         # the app closes the project when it stops
