"""Schemathesis against the studio's OpenAPI spec: no request makes a server error."""

from __future__ import annotations

import tempfile
from pathlib import Path

import schemathesis
from hypothesis import settings

from sketchanim.studio.app import create_app

APP = create_app(Path(tempfile.mkdtemp()) / "api.sketchanim", warm=False)
schema = schemathesis.openapi.from_asgi("/openapi.json", APP)


@schema.parametrize()
@settings(max_examples=10)
def test_no_server_errors(case):
    case.call_and_validate()            # every default check, not_a_server_error among them


def test_the_spec_lists_the_api():
    assert {"/api/project", "/api/state", "/api/ready"} <= set(APP.openapi()["paths"])
