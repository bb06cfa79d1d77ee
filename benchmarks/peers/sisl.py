"""SISL's data reduction (s1961, s1940) through a small C driver built against Debian's
libsisl-dev (a static library, hence -no-pie). Arrays go through pipes; SISL's own time
is measured inside the driver around the call alone."""

from __future__ import annotations

import shutil
import struct
import subprocess
from pathlib import Path

import numpy as np
from scipy.interpolate import BSpline

from peers import PeerResult

HERE = Path(__file__).resolve().parent
SOURCE = HERE / "sisl_driver.c"
BUILD = HERE.parent / ".build"


class SislUnavailable(RuntimeError):
    """libsisl-dev or gcc is missing (scripts/setup installs both)."""


def driver() -> Path:
    """Path of the compiled driver, (re)built when missing or older than its source."""
    exe = BUILD / "sisl_driver"
    if exe.exists() and exe.stat().st_mtime >= SOURCE.stat().st_mtime:
        return exe
    if shutil.which("gcc") is None or not Path("/usr/include/sisl.h").exists():
        raise SislUnavailable("SISL needs gcc and libsisl-dev: run scripts/setup")
    BUILD.mkdir(exist_ok=True)
    tmp = exe.with_suffix(".tmp")
    subprocess.run(["gcc", "-O2", "-no-pie", str(SOURCE), "-o", str(tmp), "-lsisl", "-lm"],
                   check=True, capture_output=True, text=True)
    tmp.replace(exe)
    return exe


def _run(args: list[str], times: np.ndarray, values: np.ndarray) -> tuple[BSpline, float]:
    n, dim = values.shape
    payload = struct.pack("i", n) + np.ascontiguousarray(times, "<f8").tobytes() \
        + np.ascontiguousarray(values, "<f8").tobytes()
    done = subprocess.run([str(driver()), *args], input=payload, capture_output=True, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"sisl_driver {' '.join(args)}: {done.stderr.decode().strip()}")
    out = done.stdout
    n_coef, order = struct.unpack("ii", out[:8])
    at = 8
    knots = np.frombuffer(out, "<f8", n_coef + order, at)
    at += 8 * (n_coef + order)
    coef = np.frombuffer(out, "<f8", n_coef * dim, at).reshape(n_coef, dim)
    at += 8 * (n_coef * dim + dim)
    seconds = float(np.frombuffer(out, "<f8", 1, at)[0])
    return BSpline(knots.copy(), coef.copy(), order - 1), seconds


def s1961(times: np.ndarray, values: np.ndarray, tol: np.ndarray, *, order: int = 4, split: float = 0.0) -> PeerResult:
    """Points to spline by knot removal (linear pass with ``split * tol``, then the rest),
    sample times as parameters."""
    args = ["s1961", str(values.shape[1]), str(order), repr(float(split)), *map(repr, map(float, tol))]
    spline, seconds = _run(args, times, values)
    return PeerResult(f"SISL s1961 (split {split:g})", spline, seconds)


def s1940(times: np.ndarray, values: np.ndarray, tol: np.ndarray, *, order: int = 4) -> PeerResult:
    """Knot removal on the paper's starting curve (samples as control polygon)."""
    args = ["s1940", str(values.shape[1]), str(order), *map(repr, map(float, tol))]
    spline, seconds = _run(args, times, values)
    return PeerResult("SISL s1940 (paper start)", spline, seconds)
