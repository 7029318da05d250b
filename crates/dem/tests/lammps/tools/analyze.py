#!/usr/bin/env python3
"""Physical sanity checks of each deck's per-step dump: contact, sliding, separation."""
import math, sys, os, glob
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dumpio import read_dump

MU = {"a": 0.1, "b": 0.1, "c1": 0.1, "c2": 0.1, "d": None, "e": 0.1, "f1": 0.1, "f2": 0.1, "g": 0.1}

def main(outdir):
    for path in sorted(glob.glob(os.path.join(outdir, "*.dump"))):
        if path.endswith(".pair.dump"):
            continue
        name = os.path.basename(path)[:-5]
        frames = read_dump(path)
        first = last = None; slide = 0; nsteps = 0; maxdel = 0.0
        for step, cols, rows in frames:
            c = {k: i for i, k in enumerate(cols)}
            at = [[float(x) for x in r] for r in rows]
            pairs = []
            if name.startswith("e_"):
                a = at[0]; d = a[c["radius"]] - a[c["z"]]
                if d > 0:
                    pairs.append((d, (0, 0, 1), a))
            else:
                for p in range(len(at)):
                    for q in range(p + 1, len(at)):
                        A, B = at[p], at[q]
                        dx = [A[c[k]] - B[c[k]] for k in "xyz"]
                        r = math.sqrt(sum(v * v for v in dx))
                        d = A[c["radius"]] + B[c["radius"]] - r
                        if d > 0:
                            pairs.append((d, [v / r for v in dx], A))
            if pairs:
                nsteps += 1
                first = step if first is None else first
                last = step
                maxdel = max(maxdel, max(p[0] for p in pairs))
                if len(pairs) == 1 and MU.get(name.split("_")[0]):
                    d, n, A = pairs[0]
                    fv = [A[c[k]] for k in ("fx", "fy", "fz")]
                    fn = sum(fv[k] * n[k] for k in range(3))
                    ft = math.sqrt(max(sum(v * v for v in fv) - fn * fn, 0.0))
                    if fn > 0 and ft >= 0.999999 * MU[name.split("_")[0]] * fn:
                        slide += 1
        print(f"{name}: steps {frames[0][0]}..{frames[-1][0]}, in contact {first}..{last} ({nsteps} steps with >=1 contact), "
              f"max overlap {maxdel:.3e} m, sliding steps {slide}, final contacts {len(pairs)}")

if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "decks", "out"))
