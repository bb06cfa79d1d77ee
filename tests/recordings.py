"""Real recordings for tests: ../shared/data (beside the repo) and LASA handwriting
(fetched by scripts/setup into .cache/lasa). Each case: name, times, values, tolerance."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from sketchanim.formats.csvio import read_samples_csv
from sketchanim.formats.bvh import read_bvh
from sketchanim.formats.recordings import read_lasa, read_svc, read_tum
from sketchanim.reducer.metric import rotation_angle

LASA = Path(__file__).resolve().parents[1] / ".cache" / "lasa"


def moving_root(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Times and positions of the first BVH joint whose position channels move."""
    clip = read_bvh(path)
    for j in np.flatnonzero(clip.translating):
        if np.ptp(clip.translations[:, j], axis=0).max() > 0:
            return clip.times, clip.translations[:, j]
    raise ValueError(f"{path}: no moving joint")


def shared_cases(data: Path) -> list[tuple[str, np.ndarray, np.ndarray, float]]:
    """Every channel group worth reducing in ../shared/data, with a working tolerance."""
    cases = []
    t, pos, quat = read_tum(data / "camera" / "freiburg1_xyz-groundtruth.txt")
    cases += [("tum positions (m)", t, pos, 0.005), ("tum quaternion components", t, quat, 0.005)]
    pen = read_svc(data / "pen" / "HC-female__00026_w.cz.fnusa.10_1.svc",
                   columns=("y", "x", "t", "down", "azimuth", "altitude", "pressure"), time_scale=1e-3)
    cases.append(("PaHaW pen (tablet units)", pen["t"], np.c_[pen["x"], pen["y"]], 10.0))
    pen = read_svc(data / "pen" / "bdalab_signal.svc",
                   columns=("x", "y", "t", "down", "azimuth", "altitude", "pressure"), time_scale=1.0)
    cases.append(("BDALab pen (mm)", pen["t"], np.c_[pen["x"], pen["y"]], 0.1))
    for bvh in sorted((data / "bvh").glob("*.bvh")):
        t, pos = moving_root(bvh)
        cases.append((f"{bvh.name} root", t, pos, 0.5))
    hand = np.loadtxt(data / "hand6dof" / "li_square_right_2_2.csv", delimiter=",")
    cases.append(("6-DoF hand position (mm)", hand[:, 7], hand[:, 1:4], 0.5))
    imu = read_samples_csv(data / "imu" / "ngimu_quaternion.csv")
    cases.append(("NGIMU quaternion components", imu.times, imu.values, 0.01))
    return cases


def lasa_cases() -> list[tuple[str, np.ndarray, np.ndarray, float]]:
    """All 210 LASA pen demonstrations (30 shapes x 7), tolerance 0.5 mm."""
    return [(f"LASA {mat.stem} #{i}", t, pos, 0.5)
            for mat in sorted(LASA.glob("*.mat"))
            for i, (t, pos) in enumerate(read_lasa(mat))]


def bvh_joint_rotations(path: Path, limit: int = 6) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """Up to ``limit`` joints of a BVH file whose rotation moves: name, times and
    scalar-last quaternions (from each joint's own Euler channel order, intrinsic)."""
    clip = read_bvh(path)
    out = []
    for j in np.flatnonzero(clip.rotating):
        quats = clip.rotations[:, j]
        if np.degrees(rotation_angle(quats, np.broadcast_to(quats[0], quats.shape)).max()) < 1.0:  # barely moves
            continue
        out.append((f"{path.name} {clip.skeleton.names[j]}", clip.times, quats))
        if len(out) == limit:
            break
    return out


def rotation_cases(data: Path) -> list[tuple[str, np.ndarray, np.ndarray, bool]]:
    """Real orientation channels in ../shared/data: name, times, quaternions, scalar_first."""
    t, _, quat = read_tum(data / "camera" / "freiburg1_xyz-groundtruth.txt")
    cases = [("tum camera", t, quat, False)]
    imu = read_samples_csv(data / "imu" / "ngimu_quaternion.csv")
    cases.append(("NGIMU", imu.times, imu.values, True))
    for bvh in sorted((data / "bvh").glob("*.bvh")):
        cases += [(name, times, quats, False) for name, times, quats in bvh_joint_rotations(bvh, limit=3)]
    return cases


def tum_dropped_frames(data: Path, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """82 real TUM camera positions (m) with dropped frames: 21 runs of consecutive
    100 Hz frames, split by 20 drops of 1-38 frames (intervals of 20-390 ms), from frame
    ``100 + 330 * seed`` (seeds 0-6 fit in the recording). The samples are the
    recording's own; only which frames are kept is drawn."""
    t, pos, _ = read_tum(data / "camera" / "freiburg1_xyz-groundtruth.txt")
    rng = np.random.default_rng(seed)
    runs = rng.multinomial(82 - 21, np.ones(21) / 21) + 1
    drops = np.r_[rng.integers(1, 39, 20), 0]
    keep, i = [], 100 + 330 * seed
    for run, drop in zip(runs, drops):
        keep += range(i, i + run)
        i += run + drop
    return t[keep], pos[keep]
