"""Checksums of a project's contents: a BLAKE2b digest of the document and of every
take, written in the save's transaction and checked on load, so that a damaged page is
refused by name (:meth:`.store.Project.salvage` keeps what is undamaged). A project
saved before checksums (no ``checksums`` key in ``meta``) loads unchecked and gets them
on its next save.
"""

from __future__ import annotations

import hashlib

#: The ``meta`` value saying the project carries checksums, and how they are made.
CHECKSUMS = "blake2b-128"


def document_digest(body: str) -> str:
    """The checksum of a project document's text.

    >>> len(document_digest("{}"))
    32
    """
    return hashlib.blake2b(body.encode("utf-8"), digest_size=16).hexdigest()


def take_digest(i: object, mode: object, blend: object, dim: object, n: object, times: object, vals: object) -> str:
    """The checksum of one row of the ``takes`` table (every column).

    >>> take_digest(0, "replace", 0.1, 1, 2, b"a", b"b") == take_digest(0, "replace", 0.1, 1, 2, b"a", b"c")
    False
    """
    h = hashlib.blake2b(digest_size=16)
    h.update(repr((i, mode, blend, dim, n)).encode("utf-8"))
    for blob in (times, vals):
        data = blob if isinstance(blob, bytes) else repr(blob).encode("utf-8")
        h.update(len(data).to_bytes(8, "little"))
        h.update(data)
    return h.hexdigest()


