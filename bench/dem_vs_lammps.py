#!/usr/bin/env python3
"""Side-by-side DEM speed: grains vs LAMMPS on the peer benchmark's settled beds.

Builds the beds once with ../shared/peers/dem/in.settle.lmp (untimed), then runs, for
each bed and each core count, LAMMPS (`in.bench.lmp`, 1 rank or `mpirun -np 2`) and
`grains bench dem --lammps-data BED --threads T` in turn, REPS times, and reports the
best particle-steps/s of each and their ratio per core, by wall clock and per CPU-second
(LAMMPS: loop time × its reported CPU use; grains: the process's CPU time over the timed
loop). Interleaving the two codes and keeping the best of several runs makes the ratio
robust to other load; the per-CPU-second figure also discounts time a process was
descheduled (for MPI ranks it counts their busy-waiting as work, favouring grains).

usage: python3 bench/dem_vs_lammps.py [--sizes 20000,100000] [--np 1,2] [--reps 3]
       [--steps 2000] [--work DIR] [--grains target/release/grains]
Needs: apt-get install -y lammps openmpi-bin; cargo build --release.
"""
import argparse, json, os, re, shutil, subprocess, sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PEERS = os.path.join(ROOT, "..", "shared", "peers", "dem")
SIZES = {20000: (200, 50), 100000: (1000, 50)}
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_NUM_THREADS="1")
LOOP = re.compile(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms"
                  r"(?:.|\n)*?([0-9.]+)% CPU use")


def sh(cmd, cwd):
    p = subprocess.run(cmd, cwd=cwd, env=ENV, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    return p.stdout


def lammps(work, bed, np_, steps):
    cmd = ["lmp", "-in", "in.bench.lmp", "-var", "data", bed, "-var", "nrun", str(steps)]
    if np_ > 1:
        cmd = ["mpirun", "-np", str(np_), "--bind-to", "core"] + cmd
    out = sh(cmd, work)
    # (wall rate, rate per CPU-second): LAMMPS reports the loop's wall time and its
    # average CPU use per rank.
    runs = [(int(m.group(4)) * int(m.group(3)) / float(m.group(1)),
             int(m.group(4)) * int(m.group(3)) / (float(m.group(1)) * float(m.group(5)) / 100 * int(m.group(2))))
            for m in LOOP.finditer(out) if int(m.group(3)) > 0]
    return max(runs)


def grains(exe, bed, np_, steps):
    out = sh([exe, "bench", "dem", "--lammps-data", bed, "--steps", str(steps), "--threads", str(np_)], ROOT)
    last = out.strip().splitlines()[-1]
    h = re.search(r"state-hash: (\w+)", out)
    c = re.search(r"particle-steps per cpu-s: ([0-9.eE+-]+)", out)
    return float(last.split(":")[1]), float(c.group(1)) if c else 0.0, h.group(1) if h else ""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="20000,100000")
    ap.add_argument("--np", default="1,2")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--work", default=os.path.join(ROOT, "runs", "bench_dem"))
    ap.add_argument("--grains", default=os.path.join(ROOT, "target", "release", "grains"))
    a = ap.parse_args()
    if shutil.which("lmp") is None:
        sys.exit("LAMMPS not found: apt-get install -y lammps openmpi-bin")
    os.makedirs(a.work, exist_ok=True)
    for f in ("in.settle.lmp", "in.bench.lmp"):
        shutil.copy(os.path.join(PEERS, f), a.work)
    rows = []
    for n in map(int, a.sizes.split(",")):
        nx, ny = SIZES[n]
        bed = f"bed_{n}.data"
        if not os.path.exists(os.path.join(a.work, bed)):
            print(f"settling bed_{n} with LAMMPS (untimed) ...", flush=True)
            sh(["lmp", "-in", "in.settle.lmp", "-var", "nx", str(nx), "-var", "ny", str(ny), "-var", "out", bed], a.work)
        for np_ in map(int, a.np.split(",")):
            best_l, best_lc, best_g, best_gc, hashes = 0.0, 0.0, 0.0, 0.0, set()
            for _ in range(a.reps):
                l, lc = lammps(a.work, bed, np_, a.steps)
                best_l, best_lc = max(best_l, l), max(best_lc, lc)
                g, gc, h = grains(a.grains, os.path.join(a.work, bed), np_, a.steps)
                best_g, best_gc = max(best_g, g), max(best_gc, gc)
                hashes.add(h)
            rows.append(dict(particles=n, cores=np_, lammps=best_l, grains=best_g,
                             ratio=best_g / best_l, lammps_per_cpu_s=best_lc,
                             grains_per_cpu_s=best_gc, ratio_per_cpu_s=best_gc / best_lc,
                             state_hashes=sorted(hashes)))
            print(f"N={n:6d} cores={np_}  wall: LAMMPS {best_l:.3e} ({best_l/np_:.3e}/core)  "
                  f"grains {best_g:.3e} ({best_g/np_:.3e}/core)  ratio {best_g/best_l:.2f}   "
                  f"per CPU-second: LAMMPS {best_lc:.3e}  grains {best_gc:.3e}  ratio {best_gc/best_lc:.2f}",
                  flush=True)
    with open(os.path.join(a.work, "results.json"), "w") as f:
        json.dump(rows, f, indent=1)
    print("ratio (grains / LAMMPS, same cores), wall: " + ", ".join(f"{r['particles']}@{r['cores']}: {r['ratio']:.2f}" for r in rows)
          + "; per CPU-second: " + ", ".join(f"{r['particles']}@{r['cores']}: {r['ratio_per_cpu_s']:.2f}" for r in rows))


if __name__ == "__main__":
    main()
