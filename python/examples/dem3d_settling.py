"""A 3D run from Python: the settling column (examples/dem3d/settling_column.toml, 400
spheres under Hertz–Mindlin with rolling and twisting resistance) run until at rest,
its bed's mean height sampled by a callback; then the floor's load over the column's
weight against time (from the history) and the distribution of the contact forces at
rest (from sim.contacts()), plotted with matplotlib.

    python python/examples/dem3d_settling.py [OUT.png]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import grains

ROOT = Path(__file__).resolve().parents[2]
sim = grains.Simulation.from_file(ROOT / "examples/dem3d/settling_column.toml")
assert sim.dim == 3
weight = sim.particles().mass.sum() * 9.81

times, heights = [], []


def sample(s):
    p = s.particles()  # (N, 3) positions, in id order
    times.append(s.time)
    heights.append(p.position[:, 2].mean() * 1e3)


status = sim.run(callback=sample, every=500)
h = sim.history()
load = -h["floor_fz"]  # the spheres push the floor down (−z)
c = sim.contacts()
fn = np.linalg.norm(c["normal_force"], axis=1)
ft = np.linalg.norm(c["tangential_force"], axis=1)
print(f"{status} at t = {sim.time:.3f} s after {sim.steps} steps; "
      f"floor load / weight = {load[-1] / weight:.4f}; "
      f"{len(fn)} contacts, mean normal force {fn.mean() * 1e3:.3f} mN; "
      f"state hash {sim.state_hash()}")

fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4))
ax.plot(h["time"], load / weight, color="C0", label="floor load / weight")
ax.axhline(1.0, color="k", lw=0.8, ls=":", label="full weight")
ax.set_xlabel("time (s)")
ax.set_ylabel("floor load over weight (–)", color="C0")
ax2 = ax.twinx()
ax2.plot(times, heights, "s", ms=3, color="C1", label="mean sphere height (callback)")
ax2.set_ylabel("mean sphere height (mm)", color="C1")
lines = ax.get_lines() + ax2.get_lines()
ax.legend(lines, [l.get_label() for l in lines], loc="upper right")
ax.set_title("400 spheres settling (3D)")
mean = fn.mean()
bins = np.linspace(0.0, 4.0, 41)
bx.hist(fn / mean, bins=bins, density=True, alpha=0.6, label="normal |F_n|")
bx.hist(ft / mean, bins=bins, density=True, alpha=0.6, label="tangential |F_t|")
bx.set_xlabel("contact force over the mean normal force (–)")
bx.set_ylabel("probability density (–)")
bx.set_yscale("log")
bx.legend(loc="upper right")
bx.set_title(f"contact forces at rest ({len(fn)} contacts)")
fig.tight_layout()
out = sys.argv[1] if len(sys.argv) > 1 else "dem3d_settling.png"
fig.savefig(out, dpi=120)
print(f"wrote {out}")
