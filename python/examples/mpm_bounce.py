"""An MPM run from Python: an elastic cylinder bounces in a box with frictional walls;
its centre of mass every 50 steps from the material points, plotted.

    python python/examples/mpm_bounce.py [OUT.png]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import grains

ROOT = Path(__file__).resolve().parents[2]
sim = grains.Simulation.from_file(ROOT / "crates/sim/tests/data/mpm_tiny.toml")
track = []


def record(s):
    p = s.points()
    m = p["mass"]
    track.append((s.time, *(m[:, None] * p["position"]).sum(0) / m.sum()))


record(sim)
sim.run(callback=record, every=50)
t, x, y = np.array(track).T
print(f"{sim.engine}: {sim.steps} steps to t = {sim.time:.2f} s, state {sim.state_hash()}")
fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(t, x, label="x")
ax.plot(t, y, label="y")
ax.set_xlabel("time (s)")
ax.set_ylabel("centre of mass (m)")
ax.legend(loc="best")
fig.tight_layout()
out = sys.argv[1] if len(sys.argv) > 1 else "mpm_bounce.png"
fig.savefig(out, dpi=120)
print(f"wrote {out}")
