#!/usr/bin/env python3
"""Convert each deck's LAMMPS dump (decks/out/) into compact CSV tables (tables/).

Same columns and row rule as ../lammps-granular/tools/make_tables.py: kept steps are 0..10, every 10th
step, and every step from 2 before to 9 after a change in the set of touching pairs (contact start/end).
Trajectory values are copied verbatim from the %.17g dumps. The history tables come from
tools/ref_hooke.py, which reproduces every dumped LAMMPS value bit for bit (checked here).
"""
import os, sys, glob
# dumpio.py is shared with the granular decks' tools.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from dumpio import read_dump
import ref_hooke as rh

HERE = os.path.dirname(os.path.abspath(__file__))
DECKS = os.path.join(HERE, "..", "decks")
TABLES = os.path.join(HERE, "..", "tables")
ATOM_COLS = ["x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz", "fx", "fy", "fz", "tqx", "tqy", "tqz"]
ATOM_HDR = "step,id,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz,tx,ty,tz"
R = lambda v: repr(float(v))


def main():
    os.makedirs(TABLES, exist_ok=True)
    for deckpath in sorted(glob.glob(os.path.join(DECKS, "*.in"))):
        name = os.path.basename(deckpath)[:-3]
        worst, where, nbits, sim, ref = rh.compare(name)
        assert worst == 0.0 and nbits == 0, (name, worst, where)
        dump = read_dump(os.path.join(DECKS, "out", name + ".dump"))
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
            f.write("id,radius,density,mass,x,y,z,vx,vy,vz,wx,wy,wz\n")
            for r, a in zip(rows, sim.initial):
                assert int(r[c["id"]]) == a["id"] and float(r[c["radius"]]) == a["r"] and float(r[c["mass"]]) == a["m"]
                f.write(",".join([str(a["id"]), R(a["r"]), R(a["rho"]), R(a["m"])] + [R(v) for v in a["x"] + a["v"] + a["w"]]) + "\n")
        with open(os.path.join(TABLES, name + ".history.csv"), "w") as f:
            f.write("step,i,j,s0,s1,s2,branch\n")
            for s in keep:
                step, _, hist = ref[s]
                for (i, j), (h, br) in sorted(hist.items()):
                    f.write(",".join([str(step), str(i), str(j)] + [R(v) for v in h] + [br]) + "\n")
        print(f"{name}: {len(keep)} of {nsteps} steps kept")


if __name__ == "__main__":
    main()
