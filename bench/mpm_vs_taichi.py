#!/usr/bin/env python3
"""Side-by-side speed of `grains bench mpm` and the taichi mpm88 peer script.

Both run the same problem size (N points, G x G grid, S timed steps, T threads) in
alternation, R rounds each, so both see the same background load on a shared machine.
Reported per configuration: the median over rounds of wall-clock particle-steps/s and
of particle-steps per CPU-second (process CPU time, all threads), and grains/taichi
ratios of both. The CPU-second figure is the stable one when other jobs share the cores.

Usage (from the repository root, after `cargo build --release` and `pip install taichi`):
  python3 bench/mpm_vs_taichi.py                       # the default suite
  python3 bench/mpm_vs_taichi.py --particles 32768 --grid 128 --steps 1000 --threads 1 \
      --grains-args "--bodies 2"                        # one configuration
Options: --rounds R (default 3), --peer PATH (default ../shared/peers/mpm/taichi_mpm.py),
--grains PATH (default target/release/grains), --json-out FILE (append JSON lines).
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

# (label, extra grains arguments); each against taichi mpm88 at the same N, G, S, T.
SUITE = [
    ("one body, bspline2 + USL (the peer's kernel and pass count)", "--bodies 1 --shape bspline2 --update usl"),
    ("one body, GIMP + USL", "--bodies 1 --shape gimp --update usl"),
    ("one body, GIMP + USAVG (the examples' method)", "--bodies 1 --shape gimp --update usavg"),
    ("two bodies in contact, bspline2 + USL", "--bodies 2 --shape bspline2 --update usl"),
    ("two bodies in contact, GIMP + USAVG", "--bodies 2 --shape gimp --update usavg"),
]


def run_taichi(peer, n, g, steps, threads):
    cmd = [sys.executable, peer, "--one", "--model", "mpm88", "--particles", str(n), "--grid", str(g),
           "--steps", str(steps), "--threads", str(threads), "--repeats", "1"]
    out = subprocess.run(cmd, capture_output=True, text=True)
    line = [l for l in out.stdout.splitlines() if l.startswith("RESULT ")]
    if not line:
        raise SystemExit("taichi run failed:\n" + out.stdout[-2000:] + out.stderr[-2000:])
    r = json.loads(line[0][7:])
    return r["particle_steps_per_s"], r["particle_steps_per_cpu_s"]


def run_grains(exe, n, g, steps, threads, extra):
    cmd = [exe, "bench", "mpm", "--particles", str(n), "--grid", str(g), "--steps", str(steps),
           "--threads", str(threads)] + extra.split()
    out = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    if out.returncode != 0:
        raise SystemExit("grains run failed: " + out.stderr[-2000:])
    wall = float(re.search(r"^particle-steps/s: (\S+)$", out.stdout, re.M).group(1))
    cpu = re.search(r"^particle-steps per cpu-s: (\S+)$", out.stdout, re.M)
    return wall, float(cpu.group(1)) if cpu else float("nan")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--particles", type=int, default=32768)
    ap.add_argument("--grid", type=int, default=128)
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--grains-args", default=None, help="one configuration instead of the suite")
    ap.add_argument("--peer", default=os.path.join(ROOT, "..", "shared", "peers", "mpm", "taichi_mpm.py"))
    ap.add_argument("--grains", default=os.path.join(ROOT, "target", "release", "grains"))
    ap.add_argument("--json-out", default=None)
    a = ap.parse_args()
    suite = [("custom", a.grains_args)] if a.grains_args is not None else SUITE
    n, g, s, t = a.particles, a.grid, a.steps, a.threads
    rows = []
    for label, extra in suite:
        tw, tc, gw, gc = [], [], [], []
        for _ in range(a.rounds):
            w, c = run_taichi(a.peer, n, g, s, t)
            tw.append(w)
            tc.append(c)
            w, c = run_grains(a.grains, n, g, s, t, extra)
            gw.append(w)
            gc.append(c)
        r = {
            "config": label, "grains_args": extra, "particles": n, "grid": g, "steps": s, "threads": t,
            "rounds": a.rounds,
            "taichi_wall": statistics.median(tw), "taichi_cpu": statistics.median(tc),
            "grains_wall": statistics.median(gw), "grains_cpu": statistics.median(gc),
        }
        r["ratio_wall"] = r["grains_wall"] / r["taichi_wall"]
        r["ratio_cpu"] = r["grains_cpu"] / r["taichi_cpu"]
        rows.append(r)
        print(json.dumps(r), flush=True)
        if a.json_out:
            with open(a.json_out, "a") as fh:
                fh.write(json.dumps(r) + "\n")
    print()
    print(f"N = {n}, grid {g}², {s} timed steps, {t} thread(s), median of {a.rounds} alternating rounds")
    print("| grains configuration | taichi mpm88 wall | grains wall | ratio (wall) | taichi per CPU-s | grains per CPU-s | ratio (CPU) |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['config']} (`{r['grains_args']}`) | {r['taichi_wall']/1e6:.2f} M | {r['grains_wall']/1e6:.2f} M | "
              f"{r['ratio_wall']:.2f} | {r['taichi_cpu']/1e6:.2f} M | {r['grains_cpu']/1e6:.2f} M | {r['ratio_cpu']:.2f} |")


if __name__ == "__main__":
    main()
