#!/usr/bin/env python3
"""Side-by-side 3D DEM speed: grains vs LAMMPS on the settled beds of ../shared/peers/dem3d.

Builds the beds once (untimed): the 50 k bed with the peers' in.settle3d.lmp, the 200 k bed from it with
bench/in.replicate3d.lmp. Then, per bed and core count, runs LAMMPS (the peers' in.bench3d.lmp, 1 rank or
`mpirun -np 2`) and `grains bench dem --dim 3 --lammps-data BED --threads T` in turn, REPS times, and reports the
best particle-steps/s of each and their ratio. First it checks the physics: bench/in.check3d.lmp (the same deck,
printing the kinetic energies, the highest sphere top and the floor load after the run) beside the same figures from
grains, with their relative differences.

usage: python3 bench/dem3d_vs_lammps.py [--beds 50k,200k] [--np 1,2] [--reps 3] [--steps 2000] [--work DIR]
       [--grains target/release/grains]
Needs: apt-get install -y lammps openmpi-bin; cargo build --release -p grains.
"""
import argparse, json, os, re, shutil, subprocess, sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PEERS = os.path.join(ROOT, "..", "shared", "peers", "dem3d")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_NUM_THREADS="1")
LOOP = re.compile(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms")
FIGURES = [("kinetic energy", 1), ("rotational energy", 2), ("top", 3), ("floor force", 4)]


def sh(cmd, cwd):
    p = subprocess.run(cmd, cwd=cwd, env=ENV, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    return p.stdout


def lammps(work, bed, np_):
    cmd = ["lmp", "-in", "in.bench3d.lmp", "-var", "data", bed, "-log", "none"]
    if np_ > 1:
        cmd = ["mpirun", "-np", str(np_), "--bind-to", "core"] + cmd
    out = sh(cmd, work)
    return max(int(m.group(4)) * int(m.group(3)) / float(m.group(1)) for m in LOOP.finditer(out) if int(m.group(3)) > 0)


def grains(exe, bed, np_, steps):
    out = sh([exe, "bench", "dem", "--dim", "3", "--lammps-data", bed, "--steps", str(steps), "--threads", str(np_)], ROOT)
    fig = dict(l.split(": ", 1) for l in out.strip().splitlines() if ": " in l)
    return float(fig["particle-steps/s"]), fig


def check(work, exe, bed, steps):
    """LAMMPS's thermo line after `steps` against grains' figures."""
    out = sh(["lmp", "-in", os.path.join(HERE, "in.check3d.lmp"), "-var", "data", bed, "-var", "nrun", str(steps),
              "-log", "none"], work)
    last = [l.split() for l in out.splitlines() if re.match(rf"\s*{steps}\s", l)][-1]
    _, fig = grains(exe, os.path.join(work, bed), 1, steps)
    rows = []
    for name, col in FIGURES:
        l, g = float(last[col]), float(fig[name].split()[0])
        rows.append(dict(figure=name, lammps=l, grains=g, rel=abs(g - l) / abs(l)))
        print(f"  {name:18s} LAMMPS {l:.8e}  grains {g:.8e}  rel. diff {abs(g - l) / abs(l):.2e}", flush=True)
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--beds", default="50k,200k")
    ap.add_argument("--np", default="1,2")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--work", default=os.path.join(ROOT, "runs", "bench_dem3d"))
    ap.add_argument("--grains", default=os.path.join(ROOT, "target", "release", "grains"))
    a = ap.parse_args()
    if shutil.which("lmp") is None:
        sys.exit("LAMMPS not found: apt-get install -y lammps openmpi-bin")
    os.makedirs(a.work, exist_ok=True)
    for f in ("in.settle3d.lmp", "in.bench3d.lmp"):
        shutil.copy(os.path.join(PEERS, f), a.work)
    beds = {"50k": "bed3d.data", "200k": "bed3d_200k.data"}
    if not os.path.exists(os.path.join(a.work, beds["50k"])):
        print("settling the 50 k bed with LAMMPS (untimed, 20-40 min) ...", flush=True)
        sh(["lmp", "-in", "in.settle3d.lmp", "-log", "none"], a.work)
    if "200k" in a.beds and not os.path.exists(os.path.join(a.work, beds["200k"])):
        sh(["lmp", "-in", os.path.join(HERE, "in.replicate3d.lmp"), "-log", "none"], a.work)
    rows = []
    for name in a.beds.split(","):
        bed = beds[name]
        print(f"{name}: physics after {a.steps} steps", flush=True)
        physics = check(a.work, a.grains, bed, a.steps)
        for np_ in map(int, a.np.split(",")):
            best_l, best_g, hashes = 0.0, 0.0, set()
            for _ in range(a.reps):
                best_l = max(best_l, lammps(a.work, bed, np_))
                g, fig = grains(a.grains, os.path.join(a.work, bed), np_, a.steps)
                best_g = max(best_g, g)
                hashes.add(fig.get("state-hash", ""))
            rows.append(dict(bed=name, cores=np_, lammps=best_l, grains=best_g, ratio=best_g / best_l,
                             state_hashes=sorted(hashes), physics=physics, memory=fig.get("peak memory per sphere")))
            print(f"{name} cores={np_}  LAMMPS {best_l:.3e} ({best_l/np_:.3e}/core)  grains {best_g:.3e} "
                  f"({best_g/np_:.3e}/core)  ratio {best_g/best_l:.2f}  grains memory {rows[-1]['memory']}", flush=True)
    with open(os.path.join(a.work, "results.json"), "w") as f:
        json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
