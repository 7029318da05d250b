"""A FEM–DEM run from Python: a charge in a ring of grains; every 20 steps the ring's
mean radial velocity (from the particles) and the charge's peak pressure (from its
elements), plotted against time.

    python python/examples/fem_dem_ring.py [SCENARIO] [OUT.png]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import grains

ROOT = Path(__file__).resolve().parents[2]
path = sys.argv[1] if len(sys.argv) > 1 and sys.argv[1] else ROOT / "crates/sim/tests/data/ring_tiny.toml"
sim = grains.Simulation.from_file(path)
rows = []


def record(s):
    p = s.particles()
    c = s.charge()
    centre = c["position"].mean(0)
    r = p.position - centre
    radial = np.einsum("ij,ij->i", p.velocity, r / np.linalg.norm(r, axis=1)[:, None])
    rows.append((s.time * 1e6, radial.mean(), c["pressure"].max() / 1e9))


sim.run(callback=record, every=20)
t, v, pmax = np.array(rows).T
print(f"{sim.engine}: t = {sim.time * 1e6:.2f} µs, mean radial velocity {v[-1]:.1f} m/s")
fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(t, v, color="C0", label="ring: mean radial velocity")
ax.set_xlabel("time (µs)")
ax.set_ylabel("mean radial velocity (m/s)", color="C0")
ax2 = ax.twinx()
ax2.plot(t, pmax, color="C3", label="charge: peak pressure")
ax2.set_ylabel("peak pressure (GPa)", color="C3")
lines = ax.get_lines() + ax2.get_lines()
ax.legend(lines, [l.get_label() for l in lines], loc="center right")
fig.tight_layout()
out = sys.argv[2] if len(sys.argv) > 2 else "fem_dem_ring.png"
fig.savefig(out, dpi=120)
print(f"wrote {out}")
