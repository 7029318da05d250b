"""A parameter sweep from Python: the settling column (examples/dem/settling_column.toml,
made smaller: 400 disks) at five friction coefficients, each run until at rest; the
packing fraction and the bed's height against friction, plotted with matplotlib.

    python python/examples/dem_friction_sweep.py [OUT.png]
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
base = tomllib.loads((ROOT / "examples/dem/settling_column.toml").read_text())
base["particles"][0]["count"] = 400
base["particles"][0]["region"]["hi"][1] = 0.035
base["domain"]["hi"][1] = 0.04
base["run"]["duration"] = 0.4
base["output"] = {"frames": 2, "history": 200}

frictions = [0.05, 0.2, 0.4, 0.6, 0.9]
heights, fractions = [], []
for mu in frictions:
    scenario = dict(base, material=[dict(base["material"][0], friction=mu)])
    sim = grains.Simulation.from_dict(scenario)
    status = sim.run()
    p = sim.particles()
    top = np.sort(p.position[:, 1] + p.radius)[-20:].mean()  # mean of the 20 highest tops
    width = base["domain"]["hi"][0] - base["domain"]["lo"][0]
    heights.append(top * 1e3)
    fractions.append(np.sum(np.pi * p.radius**2) / (width * top))
    print(f"mu = {mu:4.2f}: {status} at t = {sim.time:.3f} s, bed {top * 1e3:.2f} mm, "
          f"packing fraction {fractions[-1]:.4f}")

fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(frictions, fractions, "o-", color="C0", label="packing fraction")
ax.set_xlabel("friction coefficient μ (–)")
ax.set_ylabel("packing fraction of the bed (–)", color="C0")
ax2 = ax.twinx()
ax2.plot(frictions, heights, "s--", color="C1", label="bed height")
ax2.set_ylabel("bed height (mm)", color="C1")
ax.set_title("400 disks settled at rest, against friction")
lines = ax.get_lines() + ax2.get_lines()
ax.legend(lines, [l.get_label() for l in lines], loc="center right")
fig.tight_layout()
out = sys.argv[1] if len(sys.argv) > 1 else "friction_sweep.png"
fig.savefig(out, dpi=120)
print(f"wrote {out}")
