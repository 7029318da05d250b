"""Speed of the Python layer (BENCHMARKS.md, "grains from Python"): what a callback every
100 steps costs on a 20 k-disk DEM bed, particles() of 1 M disks, and a view.

    python python/bench/speed.py [--big N]

Build the package with `maturin develop --release` first.
"""

import argparse
import time

import numpy as np

import grains


def bed(n, ny_over_nx=1.0):
    """n soft disks on a lattice over a floor, periodic in x (the settling column's
    material), falling under gravity."""
    side = np.sqrt(n * 2.2e-6 / ny_over_nx)
    return {
        "name": f"bed_{n}",
        "gravity": [0.0, -9.81],
        "domain": {"lo": [0.0, 0.0], "hi": [side, side * ny_over_nx * 1.2], "periodic": [True, False]},
        "contact": {"model": "material"},
        "material": [{"name": "q", "density": 2560.0, "youngs": 5.0e6, "poisson": 0.27,
                      "restitution": 0.3, "friction": 0.3}],
        "particles": [{"source": "lattice", "material": "q",
                       "region": {"lo": [0.0, 0.001], "hi": [side, side * ny_over_nx * 1.15]},
                       "count": n, "radius": {"distribution": "uniform", "min": 0.0005, "max": 0.0007},
                       "spacing": 1.02, "speed": 0.05, "seed": 7}],
        "wall": [{"name": "floor", "shape": "segment", "a": [-1.0, 0.0], "b": [1e3, 0.0]}],
        "run": {"duration": 10.0, "safety": 0.2},
        "output": {"frames": 0, "history": 10},
    }


def best(f, k=3):
    out = []
    for _ in range(k):
        t = time.perf_counter()
        f()
        out.append(time.perf_counter() - t)
    return min(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--big", type=int, default=1_000_000)
    ap.add_argument("--steps", type=int, default=2000)
    a = ap.parse_args()

    # A callback every 100 steps against none, same bed, same steps, interleaved.
    plain, called = [], []
    for _ in range(3):
        sim = grains.Simulation.from_dict(bed(20_000))
        t = time.perf_counter()
        sim.step(a.steps)
        plain.append(time.perf_counter() - t)
        h1 = sim.state_hash()
        sim = grains.Simulation.from_dict(bed(20_000))
        seen = []
        t = time.perf_counter()
        sim.run(until=sim.dt * a.steps * (1 - 1e-9), every=100,
                callback=lambda s: seen.append(s.particles().velocity[:, 1].mean()))
        called.append(time.perf_counter() - t)
        assert sim.steps == a.steps and sim.state_hash() == h1, (sim.steps, a.steps)
    p, c = min(plain), min(called)
    print(f"20 k disks, {a.steps} steps: step() {p:.3f} s, run(every=100, callback reading "
          f"particles()) {c:.3f} s: +{100 * (c / p - 1):.1f} % (best of 3)")

    sim = grains.Simulation.from_dict(bed(a.big, 0.25))
    n = len(sim.particles())
    t = best(sim.particles, 5)
    print(f"particles() of {n} disks: {t * 1e3:.1f} ms (best of 5)")
    v = best(lambda: np.asarray(sim.view("position")), 200)
    print(f"view('position') + np.asarray on {n} disks: {v * 1e6:.1f} µs (best of 200)")


if __name__ == "__main__":
    main()
