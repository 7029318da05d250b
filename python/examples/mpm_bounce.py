"""An MPM run from Python: an elastic cylinder (crates/sim/tests/data/mpm_tiny.toml, run
for 14 s) flies to the frictional top wall of its box and bounces off; its centre of mass
every 5 steps from the material points, plotted.

    python python/examples/mpm_bounce.py [OUT.png]
"""

import sys
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import grains

ROOT = Path(__file__).resolve().parents[2]
scenario = tomllib.loads((ROOT / "crates/sim/tests/data/mpm_tiny.toml").read_text())
scenario["run"]["duration"] = 14.0
sim = grains.Simulation.from_dict(scenario)
track = []


def record(s):
    p = s.points()
    m = p["mass"]
    track.append((s.time, *(m[:, None] * p["position"]).sum(0) / m.sum()))


record(sim)
sim.run(callback=record, every=5)
t, x, y = np.array(track).T
print(f"{sim.engine}: {sim.steps} steps to t = {sim.time:.2f} s, state {sim.state_hash()}")
fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(t, x, label="x")
ax.plot(t, y, label="y")
ax.set_xlabel("time (s)")
ax.set_ylabel("centre of mass (m)")
ax.set_title("Elastic cylinder bouncing off the top wall of its box")
ax.legend(loc="lower right")
fig.tight_layout()
out = sys.argv[1] if len(sys.argv) > 1 else "mpm_bounce.png"
fig.savefig(out, dpi=120)
print(f"wrote {out}")
