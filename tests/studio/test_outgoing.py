"""A page's outgoing queue (:class:`~sketchanim.studio.app.Client`) against a socket that
does not read: the queue stays bounded, the page gets a fresh state when it reads again
and then what came after, in order; a socket blocked for too long ends the pump."""

from __future__ import annotations

import asyncio
import json
import tracemalloc

import pytest

from sketchanim.studio import app as studio_app
from sketchanim.studio.app import Client, Unread, encode


class StuckSocket:
    """A websocket whose sends block until :meth:`read` is called (a page that stopped
    reading); what it was sent, in order."""

    def __init__(self) -> None:
        self.sent: list[dict] = []
        self.reading = asyncio.Event()

    async def send_text(self, text: str) -> None:
        await self.reading.wait()
        self.sent.append(json.loads(text))

    def read(self) -> None:
        self.reading.set()


async def settle(until, rounds: int = 1000) -> None:
    """Let the pump run until ``until()`` holds."""
    for _ in range(rounds):
        if until():
            return
        await asyncio.sleep(0)
    raise AssertionError("the pump did not get there")


def values(i: int) -> dict:
    return {"type": "values", "values": {"box.position": [float(i), 0.5, 0.0]}, "n": i}


async def _fresh_state() -> dict:
    return {"type": "state", "fresh": True}


def test_a_page_that_does_not_read_keeps_the_queue_bounded_then_gets_a_state_and_what_follows(monkeypatch):
    monkeypatch.setattr(studio_app, "MAX_QUEUED", 2**18)        # 100k messages are ~25 bounds' worth

    async def run() -> None:
        socket = StuckSocket()
        client = Client(1, socket, _fresh_state)
        pump = asyncio.ensure_future(client.pump())
        client.put({"type": "state", "first": True})
        await asyncio.sleep(0)                                   # the pump is stuck sending it
        one = len(encode(values(0)))
        tracemalloc.start()
        for i in range(100_000):
            client.put(values(i))
            client.put({"type": "preview", "key": f"k{i % 7}", "path": "box.position", "value": [i, 0, 0]})
            assert client.queued <= studio_app.MAX_QUEUED
        held, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        assert client.stale and client.queued == 0 and not client.queue and not client.previews
        assert 100_000 * one > 20 * studio_app.MAX_QUEUED        # 100k messages and 100k previews were put ...
        assert peak < 4 * studio_app.MAX_QUEUED                  # ... and the queue held a bound's worth
        socket.read()
        await settle(lambda: not client.stale and len(socket.sent) == 2)
        client.put(values(-1))
        client.put(values(-2))
        await settle(lambda: len(socket.sent) == 4)
        pump.cancel()
        assert [m.get("first") or m.get("fresh") or m["n"] for m in socket.sent] == [True, True, -1, -2]

    asyncio.run(run())


def test_the_latest_preview_of_a_key_goes_out_once_after_the_queue():
    async def run() -> None:
        socket = StuckSocket()
        client = Client(1, socket, _fresh_state)
        for i in range(5):
            client.put({"type": "preview", "key": "drag", "path": "box.position", "value": [i, 0, 0]})
        client.put(values(1))
        assert client.queued == len(encode(values(1))) + len(encode(
            {"type": "preview", "key": "drag", "path": "box.position", "value": [4, 0, 0]}))
        socket.read()
        pump = asyncio.ensure_future(client.pump())
        await settle(lambda: len(socket.sent) == 2)
        pump.cancel()
        assert [m["type"] for m in socket.sent] == ["values", "preview"] and socket.sent[1]["value"] == [4, 0, 0]
        assert client.queued == 0

    asyncio.run(run())


def test_one_message_larger_than_the_bound_still_goes_out(monkeypatch):
    monkeypatch.setattr(studio_app, "MAX_QUEUED", 100)
    client = Client(1, StuckSocket(), _fresh_state)
    big = {"type": "state", "pad": "x" * 500}
    client.put(big)
    assert not client.stale and list(client.queue) == [encode(big)]
    client.put(values(1))                                      # over the bound with a backlog: dropped for a state
    assert client.stale and not client.queue


def test_a_send_blocked_too_long_ends_the_pump(monkeypatch):
    monkeypatch.setattr(studio_app, "SEND_TIMEOUT", 0.05)

    async def run() -> None:
        client = Client(1, StuckSocket(), _fresh_state)
        client.put(values(1))
        with pytest.raises(Unread, match="page 1 has read nothing"):
            await client.pump()

    asyncio.run(run())
