"""Generate the shipped example take (run from the repository root; output is committed).

A hand-held 3D path as an animator might sketch it with a tracked controller: a
widening spiral with a slow vertical sway, a one-second hold in the middle, hand
tremor (1.5 mm), sampled at 60 Hz with the jitter of a real input loop.
"""

from pathlib import Path

import numpy as np

rng = np.random.default_rng(1995)
dt = 1 / 60 + rng.normal(0.0, 0.0008, 12 * 60)
t = np.cumsum(np.clip(dt, 0.012, 0.022))
t -= t[0]
hold = (t > 5.5) & (t < 6.5)
s = np.where(t < 5.5, t, np.where(hold, 5.5, t - 1.0))  # progress along the path stops while holding
angle = 1.1 * s
radius = 0.15 + 0.06 * s
x = radius * np.cos(angle)
y = radius * np.sin(angle)
z = 1.2 + 0.25 * np.sin(0.7 * s) + 0.05 * s
path = np.c_[x, y, z] + rng.normal(0.0, 0.0015, (len(t), 3))
out = Path(__file__).with_name("sketched_path.csv")
np.savetxt(out, np.c_[t, path], delimiter=",", header="t,x,y,z", comments="", fmt="%.6f")
print(f"wrote {out}: {len(t)} samples over {t[-1]:.2f} s")
