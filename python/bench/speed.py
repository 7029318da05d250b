"""Speed of the Python layer (BENCHMARKS.md, "grains from Python"): what a callback every
100 steps costs on a 20 k-disk DEM bed, particles() of 1 M disks, and a view.

    python python/bench/speed.py [--big N] [--bed bed_20000.data --grains target/release/grains]

Build the package with `maturin develop --release` first. With `--bed` (the peer
benchmark's settled bed, as `bench/dem_vs_lammps.py` makes it with LAMMPS), the
callback run is also timed against `grains bench dem --lammps-data BED` on that bed with
the same physics, interleaved, and both must end with the same state hash.
"""

import argparse
import os
import re
import subprocess
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


def bench_bed(path, steps):
    """The scenario `grains bench dem --lammps-data path` runs (crates/sim/src/bench/dem.rs):
    LAMMPS gran/hooke/history, kn 4000, kt 2/7 kn, γn 87, γt γn/2, μ 0.3, density 1,
    g = 1, Δt 5e-4, skin 0.1, a floor at y = 0, periodic in x."""
    lines = open(path).read().splitlines()
    lo, hi = [0.0, 0.0], [0.0, 0.0]
    for ln in lines:
        w = ln.split()
        for k, axis in enumerate(("x", "y")):
            if len(w) >= 4 and w[2:4] == [f"{axis}lo", f"{axis}hi"]:
                lo[k], hi[k] = float(w[0]), float(w[1])
    start = next(i for i, ln in enumerate(lines) if ln.startswith("Atoms"))
    top = hi[1]
    for ln in lines[start + 2:]:
        w = ln.split()
        if not w:
            break
        top = max(top, float(w[5]))
    dt = 5e-4
    return {
        "name": "bench_bed",
        "gravity": [0.0, -1.0],
        "domain": {"lo": [lo[0], min(lo[1], 0.0)], "hi": [hi[0], top + 1.0], "periodic": [True, False]},
        "contact": {"model": "hooke_history", "kn": 4000.0, "kt": 4000.0 * 2 / 7,
                    "gamma_n": 87.0, "gamma_t": 43.5, "mu": 0.3},
        "material": [{"name": "bench", "density": 1.0, "inertia_factor": 0.4}],
        "particles": [{"source": "lammps_data", "material": "bench", "path": path}],
        "wall": [{"name": "floor", "shape": "segment", "a": [-1e9, 0.0], "b": [1e9, 0.0]}],
        "run": {"duration": 2 * steps * dt, "dt": dt, "skin": 0.1},
        "output": {"frames": 0, "history": 2},
    }


def against_bench(bed_path, exe, steps, threads, reps=3):
    """`sim.run(every=100, callback=…)` on the bench bed against `grains bench dem` on it,
    interleaved; wall seconds of the stepping alone in both."""
    bed_path = os.path.abspath(bed_path)
    cmd = [exe, "bench", "dem", "--lammps-data", bed_path, "--steps", str(steps), "--threads", str(threads)]
    bench, called, hashes = [], [], {}
    for _ in range(reps):
        out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
        bench.append(float(re.search(r"wall time: ([0-9.]+) s", out).group(1)))
        hashes.setdefault("bench", set()).add(re.search(r"state-hash: (\w+)", out).group(1))
        sim = grains.Simulation.from_dict(bench_bed(bed_path, steps))
        seen = []
        t = time.perf_counter()
        sim.run(until=sim.dt * steps * (1 - 1e-9), every=100,
                callback=lambda s: seen.append(s.particles().velocity[:, 1].mean()))
        called.append(time.perf_counter() - t)
        assert sim.steps == steps, (sim.steps, steps)
        hashes.setdefault("python", set()).add(sim.state_hash())
    b, c = min(bench), min(called)
    same = "the same state hash" if len(set().union(*hashes.values())) == 1 else f"DIFFERENT state hashes {hashes}"
    print(f"bench bed {bed_path}, {steps} steps, {threads} thread(s): `grains bench dem` {b:.3f} s, "
          f"run(every=100, callback reading particles()) {c:.3f} s: +{100 * (c / b - 1):.1f} % "
          f"(best of {reps}, interleaved; {same})")


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
    ap.add_argument("--bed", help="the peer benchmark's bed (LAMMPS data) to time against grains bench dem")
    ap.add_argument("--grains", default="target/release/grains", help="the grains binary for --bed")
    a = ap.parse_args()

    if a.bed:
        # The package steps on rayon's global pool, one thread per core: so does the bench.
        against_bench(a.bed, a.grains, a.steps, os.cpu_count())

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
