#!/usr/bin/env python3
"""Convert each deck's LAMMPS dumps (decks/out/) into compact CSV tables (tables/).

Kept steps: 0..10, every 10th step, and every step from 2 steps before to 9 steps after a change in the set of
touching pairs (contact start/end). Values are copied verbatim from the %.17g dumps; the history
tables come from tools/ref_granular.py, which reproduces every dumped LAMMPS field bit for bit.
"""
import os, sys, glob
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dumpio import read_dump
import ref_granular as rg

HERE = os.path.dirname(os.path.abspath(__file__))
DECKS = os.path.join(HERE, "..", "decks")
TABLES = os.path.join(HERE, "..", "tables")
ATOM_COLS = ["x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz", "fx", "fy", "fz", "tqx", "tqy", "tqz"]
ATOM_HDR = "step,id,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz,tx,ty,tz"


def hist_names(law):
    names = []
    if law["tangential"] != "linear_nohistory":
        names += ["t0", "t1", "t2"]
        if law["tangential"].startswith("mindlin_rescale"):
            names.append("a_prev")
    if law["roll"]:
        names += ["r0", "r1", "r2"]
    if law["twist"]:
        names.append("tw")
    return names


def main():
    os.makedirs(TABLES, exist_ok=True)
    for deckpath in sorted(glob.glob(os.path.join(DECKS, "*.in"))):
        name = os.path.basename(deckpath)[:-3]
        worst, where, sim, ref = rg.compare(name)
        # Bit for bit but where two contacts meet on one atom (f3: their sum, 1 ulp).
        assert worst <= 1e-14, (name, worst, where)
        dump = read_dump(os.path.join(DECKS, "out", name + ".dump"))
        pdump = read_dump(os.path.join(DECKS, "out", name + ".pair.dump"))
        contacts = [frozenset(h.keys()) for (_, _, h) in ref]
        nsteps = len(dump)
        change = set()
        for s in range(1, nsteps):
            if contacts[s] != contacts[s - 1]:
                change.update(range(max(0, s - 2), min(nsteps, s + 10)))
        keep = [s for s in range(nsteps) if s <= 10 or s % 10 == 0 or s in change]
        with open(os.path.join(TABLES, name + ".csv"), "w") as f:
            f.write(ATOM_HDR + "\n")
            for s in keep:
                step, cols, rows = dump[s]
                c = {k: i for i, k in enumerate(cols)}
                for r in rows:
                    f.write(",".join([str(step), r[c["id"]]] + [r[c[k]] for k in ATOM_COLS]) + "\n")
        with open(os.path.join(TABLES, name + ".atoms.csv"), "w") as f:
            step, cols, rows = dump[0]
            c = {k: i for i, k in enumerate(cols)}
            f.write("id,type,radius,mass\n")
            for r in rows:
                f.write(",".join(r[c[k]] for k in ("id", "type", "radius", "mass")) + "\n")
        laws = dict(sim.laws)
        with open(os.path.join(TABLES, name + ".history.csv"), "w") as f:
            names = None
            for s in keep:
                step, _, hist = ref[s]
                for (i, j), h in sorted(hist.items()):
                    if j == 0:
                        law = sim.wall
                    else:
                        ti = sim.atoms[i - 1]["type"]; tj = sim.atoms[j - 1]["type"]
                        law = sim.law(ti, tj)
                    hn = hist_names(law)
                    if names is None:
                        names = hn
                        f.write("step,i,j," + ",".join(names) + "\n")
                    assert hn == names
                    f.write(",".join([str(step), str(i), str(j)] + [repr(float(v)) for v in h]) + "\n")
        with open(os.path.join(TABLES, name + ".pair.csv"), "w") as f:
            f.write("step,i,j," + ",".join(f"p{k}" for k in range(1, 13)) + "\n")
            for s in keep:
                step, cols, rows = pdump[s]
                for r in rows:
                    vals = r[3:15]
                    if any(float(v) != 0.0 for v in vals):
                        f.write(",".join([str(step), r[1], r[2]] + vals) + "\n")
        print(f"{name}: {len(keep)} of {nsteps} steps kept")


if __name__ == "__main__":
    main()
