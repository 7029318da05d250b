#!/usr/bin/env python3
"""Physical sanity check of each deck's dump: contact window, overlap, normal restitution, normal turning,
energy loss, and the stick/slip sequence (from tools/ref_hooke.py: S = slip, . = stick, per contact step)."""
import math, os, sys, glob
# dumpio.py is shared with the granular decks' tools.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from dumpio import read_dump
import ref_hooke as rh

HERE = os.path.dirname(os.path.abspath(__file__))
DECKS = os.path.join(HERE, "..", "decks")


def main():
    for path in sorted(glob.glob(os.path.join(DECKS, "*.in"))):
        name = os.path.basename(path)[:-3]
        _, _, _, sim, ref = rh.compare(name)
        dim_disc = sim.disc
        dump = read_dump(os.path.join(DECKS, "out", name + ".dump"))
        def state(s):
            step, cols, rows = dump[s]
            c = {k: i for i, k in enumerate(cols)}
            return [{k: float(r[c[k]]) for k in cols} for r in rows]
        def ke(at):
            e = 0.0
            for a in at:
                I = (0.5 if dim_disc else 0.4) * a["mass"] * a["radius"] ** 2
                e += 0.5 * a["mass"] * (a["vx"] ** 2 + a["vy"] ** 2 + a["vz"] ** 2)
                e += 0.5 * I * (a["omegax"] ** 2 + a["omegay"] ** 2 + a["omegaz"] ** 2)
            return e
        keys = sorted({k for (_, _, h) in ref for k in h})
        print(f"{name}: KE(trans+rot) {ke(state(0)):.4e} J -> {ke(state(len(dump) - 1)):.4e} J")
        for key in keys:
            steps = [s for s, (_, _, h) in enumerate(ref) if key in h]
            seq = "".join({"slip": "S", "stick": ".", "slip0": "0"}[ref[s][2][key][1]] for s in steps)
            i, j = key
            def nv(s):
                at = state(s)
                A = at[i - 1]
                if j == 0:
                    d = [0.0, 0.0, A["z"]]; vr = [A["vx"], A["vy"], A["vz"]]; rs = A["radius"]
                else:
                    B = at[j - 1]
                    d = [A[k] - B[k] for k in "xyz"]; vr = [A["v" + k] - B["v" + k] for k in "xyz"]
                    rs = A["radius"] + B["radius"]
                r = math.sqrt(sum(x * x for x in d)); n = [x / r for x in d]
                return n, sum(vr[k] * n[k] for k in range(3)), rs - r
            n0, vn0, _ = nv(steps[0] - 1)
            n1, vn1, _ = nv(steps[-1] + 1)
            turn = math.degrees(math.acos(max(-1.0, min(1.0, sum(a * b for a, b in zip(n0, n1))))))
            maxd = max(nv(s)[2] for s in steps)
            contig = steps == list(range(steps[0], steps[-1] + 1))
            print(f"  contact {key}: steps {steps[0]}..{steps[-1]} ({len(steps)} steps, contiguous {contig}), max overlap {maxd:.3e} m, "
                  f"v_n {vn0:+.4f} -> {vn1:+.4f} m/s (e = {-vn1 / vn0:.3f}), normal turned {turn:.1f} deg, "
                  f"slip {seq.count('S')} / stick {seq.count('.')}")
            print(f"    {seq}")
        last = ref[-1][2]
        print(f"  contacts at the end: {sorted(last)}")


if __name__ == "__main__":
    main()
