#!/usr/bin/env python3
"""What grains sends between ranks, measured on 1-8 ranks and extrapolated to 64
(docs/parallel.md, "Past this machine"). Python 3 standard library only.

    python3 bench/comm_scale.py measure --grains BIN [--out DIR] [--only 2d|3d]
                                        [--ranks 1,2,4,8]
        2D: `mpirun -np N grains bench dem --lammps-data bed_20000.data --tile T`
        (weak: 30 k disks per rank; strong: 120 k disks), 3D: `mpirun -np N grains run`
        of a sphere lattice, 8 k spheres per rank (weak) and 32 k in all (strong);
        writes DIR/measured.json and prints the tables.
    python3 bench/comm_scale.py model
        the model: ghosts at 64 ranks, and xue-2019 test 1 on 16 and 64 cores.
    python3 bench/comm_scale.py tables DIR/measured.json
        the measured tables again.
"""

import argparse
import json
import math
import os
import re
import subprocess
import sys

MPIRUN = ["mpirun", "--allow-run-as-root", "--oversubscribe",
          "--mca", "mpi_yield_when_idle", "1"]

# ---------------------------------------------------------------- measuring


def bench_2d(grains, bed, ranks, tile, steps):
    """One `grains bench dem` on `ranks` ranks: its report as a dict of lines."""
    cmd = ([] if ranks == 1 else MPIRUN + ["-np", str(ranks)]) + [
        grains, "bench", "dem", "--lammps-data", bed, "--tile", str(tile),
        "--steps", str(steps), "--threads", "1"]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    lines = dict(l.split(": ", 1) for l in out.splitlines() if ": " in l)
    return {"cmd": " ".join(cmd), "lines": lines}


# A sphere lattice of 20 x 20 x 20 per rank (pitch 2 r_max x 1.02), periodic in x and
# y, on a floor: the 3D weak-scaling box.
PITCH = 2 * 0.002 * 1.02
SIDE = 20 * PITCH

SCENARIO_3D = """engine = "dem"
dim = 3
name = "lattice3d_{n}"
description = "{n} spheres on a cubic lattice, periodic in x and y, on a floor"
gravity = [0.0, 0.0, -9.81]

[domain]
lo = [0.0, 0.0, 0.0]
hi = [{x}, {y}, {z}]
periodic = [true, true, false]

[[material]]
name = "soft"
density = 2500.0
youngs = 1.0e7
poisson = 0.3
restitution = 0.3
friction = 0.5

[contact]
model = "granular"
normal = "hertz/material"
damping = "restitution"
tangential = "mindlin"

[[wall]]
shape = "plane"
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]

[[particles]]
source = "lattice"
material = "soft"
region = {{ shape = "box", lo = [0.0, 0.0, 0.0], hi = [{x}, {y}, {zl}] }}
count = {n}
radius = {{ distribution = "uniform", min = 0.0019, max = 0.002 }}
spacing = 1.02
speed = 0.05
seed = 3

[run]
duration = {duration}
safety = 0.2

[output]
frames = 1
history = 20
"""


def lattice_3d(cells, duration):
    """The scenario text of a lattice `cells` = (cx, cy, cz) rank boxes big."""
    cx, cy, cz = cells
    n = 8000 * cx * cy * cz
    x, y, zl = cx * SIDE, cy * SIDE, cz * SIDE
    return SCENARIO_3D.format(n=n, x=x, y=y, zl=zl, z=zl + 3 * PITCH,
                              duration=duration)


def run_3d(grains, out, ranks, cells, duration):
    """`grains run` of the lattice on `ranks` ranks: the summary's counts."""
    name = "lattice3d_{}x{}x{}_n{}".format(*cells, ranks)
    path = os.path.join(out, name + ".toml")
    with open(path, "w") as f:
        f.write(lattice_3d(cells, duration))
    run_dir = os.path.join(out, name)
    cmd = ([] if ranks == 1 else MPIRUN + ["-np", str(ranks)]) + [
        grains, "run", path, "--out", run_dir, "--threads", "1"]
    subprocess.run(cmd, capture_output=True, text=True, check=True)
    with open(os.path.join(run_dir, "summary.json")) as f:
        s = json.load(f)
    # `counts` are written at the summary's top level.
    keys = ["ghost_fraction", "comm_bytes_per_step", "comm", "neighbour_builds"]
    return {"cmd": " ".join(cmd), "particles": s["particles"], "steps": s["steps"],
            "counts": {k: s[k] for k in keys if k in s}, "state_hash": s["state_hash"]}


def measure(args):
    os.makedirs(args.out, exist_ok=True)
    ranks = [int(r) for r in args.ranks.split(",")]
    res = {"weak2d": [], "strong2d": [], "weak3d": [], "strong3d": []}
    if args.only in (None, "2d"):
        tiles = {1: 2, 2: 3, 4: 6, 8: 12}
        for n in ranks:
            res["weak2d"].append(dict(ranks=n, **bench_2d(args.grains, args.bed, n, tiles[n], args.steps)))
        for n in ranks:
            res["strong2d"].append(dict(ranks=n, **bench_2d(args.grains, args.bed, n, 6, args.steps)))
    if args.only in (None, "3d"):
        weak = {1: (1, 1, 1), 2: (2, 1, 1), 4: (2, 2, 1), 8: (2, 2, 2)}
        for n in ranks:
            res["weak3d"].append(dict(ranks=n, **run_3d(args.grains, args.out, n, weak[n], args.duration)))
        for n in ranks:
            res["strong3d"].append(dict(ranks=n, **run_3d(args.grains, args.out, n, (2, 2, 1), args.duration)))
    path = os.path.join(args.out, "measured.json")
    with open(path, "w") as f:
        json.dump(res, f, indent=1)
    print("wrote", path)
    tables(res)


# ------------------------------------------------------------ reading them


def bench_row(r):
    """(ranks, particles, ghost fraction, bytes per step by stage) of a 2D bench."""
    l = r["lines"]
    row = {"ranks": r["ranks"], "particles": int(l["particles"]),
           "grid": l.get("ranks", "1").split("grid ")[-1].rstrip(")")}
    row["ghost_fraction"] = float(l.get("ghosts per owned particle", 0))
    for k in ["ghosts", "rebuild", "reductions", "ledger"]:
        m = re.match(r"([\d.]+) messages, ([\d.]+) collectives, (\d+) B sent, (\d+) B received",
                     l.get("comm " + k, "0 messages, 0 collectives, 0 B sent, 0 B received"))
        row[k] = {"messages": float(m[1]), "collectives": float(m[2]),
                  "sent": float(m[3]), "received": float(m[4])}
    m = re.match(r"(\d+) B sent per rank \((\d+) rebuilds", l.get("comm per rebuild", "0 B sent per rank (0 rebuilds"))
    row["per_rebuild"], row["rebuilds"] = float(m[1]), int(m[2])
    row["state_hash"] = l.get("state-hash")
    return row


def run_row(r):
    """The same from a `grains run` summary."""
    c = r["counts"]
    row = {"ranks": r["ranks"], "particles": r["particles"], "grid": "auto",
           "ghost_fraction": c.get("ghost_fraction", 0.0)}
    per = c.get("comm", {}).get("per_rank_and_step", {})
    for k in ["ghosts", "rebuild", "reductions", "ledger"]:
        f = per.get(k, {})
        row[k] = {"messages": f.get("messages", 0), "collectives": f.get("collectives", 0),
                  "sent": f.get("bytes_sent", 0), "received": f.get("bytes_received", 0)}
    row["per_rebuild"] = c.get("comm", {}).get("bytes_per_rebuild", 0)
    row["rebuilds"] = c.get("comm", {}).get("rebuilds", 0)
    row["state_hash"] = r["state_hash"]
    return row


def tables(res):
    for key, read in [("weak2d", bench_row), ("strong2d", bench_row),
                      ("weak3d", run_row), ("strong3d", run_row)]:
        print("\n" + key)
        print("| ranks | particles | ghosts per owned | ghost refresh B/step (msgs) | "
              "reductions B/step (calls) | ledger B sent / received per step | "
              "rebuilds | B per rebuild | state hash |")
        print("|---|---|---|---|---|---|---|---|---|")
        for r in res[key]:
            w = read(r)
            print("| {} | {:,} | {:.4f} | {:,.0f} ({:.0f}) | {:,.0f} ({:.1f}) | {:,.0f} / {:,.0f} | {} | {:,.0f} | {} |".format(
                w["ranks"], w["particles"], w["ghost_fraction"], w["ghosts"]["sent"],
                w["ghosts"]["messages"], w["reductions"]["sent"], w["reductions"]["collectives"],
                w["ledger"]["sent"], w["ledger"]["received"], w["rebuilds"], w["per_rebuild"],
                w["state_hash"]))


# ------------------------------------------------------------------ the model

# Bytes per ghost per step (position, velocity, spin, force, torque as f64), and per
# ghost sent whole at a rebuild (every field: `decomp::words::put_particle`).
MOTION = {2: 8 * 8, 3: 15 * 8}
WHOLE = {2: 13 * 8, 3: 22 * 8}
# The energy ledger: each particle keeps its own running ledger, and the ranks sum
# their particles' exactly (19 exact sums of 71 words each, from every rank) only when
# the figures are asked for: a history sample (or a gather).
LEDGER_SUM = 19 * 71 * 8
# The step's other collectives (measured on the 2D bed, one wall: 7 a step, 1,808 B
# from each rank, the wall loads' exact sums 1,704 of them).
REDUCTIONS, REDUCTION_BYTES = 7, 1808

# Networks: (bandwidth B/s, latency s) per message (sources in docs/parallel.md).
NETS = {"100 Gb/s InfiniBand": (12.5e9, 1.5e-6), "10 GbE": (1.25e9, 20e-6)}

# xue-2019 test 1 (BENCHMARKS.md, "Test 1 at full size"): disks, steps to 100 us, list
# builds with the expanding frame, wall time on 2 idle cores (s), the annulus (m).
T1 = dict(n=1_803_137, steps=114_118, builds=3_098, wall=(8_700, 9_400),
          r_in=0.010, r_out=0.030, d0=38.4e-6, samples=500)
# The halo of a ring in mean diameters: 2 r_max + skin, r_max = d0 (1 + 3 delta) / 2,
# skin = d0 / 2 (blast/assemble.rs).
T1_HALO = (1 + 3 * 0.113) + 0.5
# Rebuilds without the expanding frame (refused on ranks): test 2 took 4,087 builds
# under the classic rule against 1,371 in the frame (BENCHMARKS.md), and ring_small_40
# 21.36 s user against 19.93 s (+7 % compute).
CLASSIC_BUILDS, CLASSIC_COMPUTE = 4087 / 1371, 21.36 / 19.93


def ghosts_square(dim, n, density, halo, faces=None):
    """Ghosts of a square (cubic) box of `n` particles at `density`, with neighbours
    across every face (an interior box), ghost layer `halo` wide: faces, edges and
    corners of the shell."""
    side = (n / density) ** (1.0 / dim)
    if dim == 2:
        return density * (4 * side * halo + 4 * halo ** 2)
    return density * (6 * side ** 2 * halo + 12 * side * halo ** 2 + 8 * halo ** 3)


def annulus_grid(p_side, r_in, r_out, halo, samples=400_000, seed=1):
    """An annulus (uniform density) on a p_side x p_side product grid whose cuts sit at
    the quantiles along x and y (what `decomp::balance` does): per box the share of
    the particles it owns and the share it holds as ghosts (within `halo` of the box),
    by sampling."""
    import random
    rnd = random.Random(seed)
    pts = []
    while len(pts) < samples:
        x, y = rnd.uniform(-r_out, r_out), rnd.uniform(-r_out, r_out)
        if r_in ** 2 <= x * x + y * y <= r_out ** 2:
            pts.append((x, y))
    def cuts(v):
        v = sorted(v)
        return [v[len(v) * k // p_side] for k in range(1, p_side)]
    cx, cy = cuts([p[0] for p in pts]), cuts([p[1] for p in pts])
    ex = [-r_out] + cx + [r_out]
    ey = [-r_out] + cy + [r_out]
    import bisect
    own = [[0] * p_side for _ in range(p_side)]
    ghost = [[0] * p_side for _ in range(p_side)]
    for x, y in pts:
        i, j = bisect.bisect(cx, x), bisect.bisect(cy, y)
        own[i][j] += 1
        # Boxes other than its own within `halo`: the 3 x 3 around it suffice.
        for a in range(max(0, i - 1), min(p_side, i + 2)):
            for b in range(max(0, j - 1), min(p_side, j + 2)):
                if (a, b) == (i, j):
                    continue
                dx = max(ex[a] - x, 0.0, x - ex[a + 1])
                dy = max(ey[b] - y, 0.0, y - ey[b + 1])
                if dx * dx + dy * dy <= halo * halo:
                    ghost[a][b] += 1
    boxes = [(own[i][j] / samples, ghost[i][j] / samples)
             for i in range(p_side) for j in range(p_side)]
    return boxes


def allgather(p, bytes_each, bw, lat):
    """An all-gather of `bytes_each` from each of `p` ranks: recursive doubling,
    log2 p latencies and (p - 1) shares through each rank's link."""
    if p == 1:
        return 0.0
    return math.ceil(math.log2(p)) * lat + (p - 1) * bytes_each / bw


def step_time(p, n_rank, ghosts, neighbours, n_total, c, bw, lat, ledger=True,
              steps_per_build=None, dim=2, samples_per_step=0.0):
    """Seconds one step takes on the busiest rank: compute, the ghost refresh, the
    step's collectives, the ledger's sums at samples (spread over the steps), a
    rebuild's share."""
    t = {"compute": c * (n_rank + ghosts)}
    t["ghosts"] = neighbours * lat + MOTION[dim] * ghosts / bw
    t["reductions"] = REDUCTIONS * allgather(p, REDUCTION_BYTES / REDUCTIONS, bw, lat)
    t["ledger"] = samples_per_step * allgather(p, LEDGER_SUM, bw, lat) if ledger else 0.0
    if steps_per_build:
        t["rebuild"] = (2 * neighbours * lat + WHOLE[dim] * ghosts / bw) / steps_per_build
    return t


def model(args):
    lines = []
    say = lines.append
    n, steps = T1["n"], T1["steps"]
    c = [2 * w / (n * steps) for w in T1["wall"]]
    say(f"test 1, one core per disk-step: {c[0] * 1e9:.1f}-{c[1] * 1e9:.1f} ns "
        f"(2 cores x {T1['wall'][0]}-{T1['wall'][1]} s / {n:,} disks / {steps:,} steps)")
    rho = n * T1["d0"] ** 2 / (math.pi * (T1["r_out"] ** 2 - T1["r_in"] ** 2))
    say(f"ring density {rho:.3f} disks per d0^2, halo {T1_HALO:.2f} d0")
    # 64 ranks of the beds, interior boxes.
    rho2 = 20000 / (200 * 88.33459118521913)
    g2 = ghosts_square(2, 30000, rho2, 0.98 + 0.1)
    say(f"2D bed, 30 k disks per square box (interior, 8 neighbours): {g2:.0f} ghosts, "
        f"fraction {g2 / 30000:.4f}; refresh {g2 * MOTION[2] / 1e3:.1f} kB per step")
    # 3D: the settled bed3d.data (50,184 spheres, d 0.9-1.1, skin 0.2) fills about
    # 50,184 / 0.61 x (pi/6) volume; take its number density from a packing fraction 0.6.
    rho3 = 0.6 / (math.pi / 6 * 1.0)
    g3 = ghosts_square(3, 8000, rho3, 1.1 + 0.2)
    say(f"3D bed, 8 k spheres per cube (interior, 26 neighbours): {g3:.0f} ghosts, "
        f"fraction {g3 / 8000:.3f}; refresh {g3 * MOTION[3] / 1e3:.1f} kB per step")
    for cores in [16, 64]:
        side = int(round(math.sqrt(cores)))
        boxes = annulus_grid(side, T1["r_in"], T1["r_out"], T1_HALO * T1["d0"],
                             samples=args.samples)
        owned = max(b[0] for b in boxes) * n
        busiest = max(boxes, key=lambda b: b[0])
        ghosts = busiest[1] * n
        mean = n / cores
        gsum = sum(b[1] for b in boxes) * n
        say(f"\ntest 1 on {cores} cores ({side} x {side}, cuts at quantiles): mean "
            f"{mean:,.0f} disks per rank, busiest {owned:,.0f} (x{owned / mean:.2f}) with "
            f"{ghosts:,.0f} ghosts; ghosts per owned over all ranks {gsum / n:.4f}")
        for net, (bw, lat) in NETS.items():
            for ledger in [True, False]:
                for cc in c:
                    t = step_time(cores, owned, ghosts, 8, n, cc * CLASSIC_COMPUTE, bw, lat,
                                  ledger=ledger, steps_per_build=steps / (T1["builds"] * CLASSIC_BUILDS),
                                  samples_per_step=T1["samples"] / steps)
                    total = sum(t.values()) * steps
                    parts = ", ".join(f"{k} {v * 1e3:.3f}" for k, v in t.items())
                    say(f"  {net}, ledger {'on ' if ledger else 'off'}, c {cc * 1e9:.0f} ns: "
                        f"{total:,.0f} s ({total / 3600:.2f} h); per step ms: {parts}")
    print("\n".join(lines))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="what", required=True)
    m = sub.add_parser("measure")
    m.add_argument("--grains", required=True, help="a grains binary built with --features mpi")
    m.add_argument("--bed", default="/work/bed2d/bed_20000.data")
    m.add_argument("--steps", type=int, default=1000)
    m.add_argument("--duration", type=float, default=0.007, help="3D run length (s)")
    m.add_argument("--out", default="runs/comm_scale")
    m.add_argument("--only", choices=["2d", "3d"], help="one dimension's runs only")
    m.add_argument("--ranks", default="1,2,4,8", help="rank counts (of 1, 2, 4, 8)")
    t = sub.add_parser("tables")
    t.add_argument("measured")
    o = sub.add_parser("model")
    o.add_argument("--samples", type=int, default=400_000, help="points sampling the annulus")
    a = p.parse_args()
    if a.what == "measure":
        measure(a)
    elif a.what == "tables":
        with open(a.measured) as f:
            tables(json.load(f))
    else:
        model(a)


if __name__ == "__main__":
    sys.exit(main())
