#!/usr/bin/env python3
"""Plain-Python transcription of LAMMPS 29Sep2021 pair gran/hooke/history (pair_gran_hooke_history.cpp
compute()), fix wall/gran hooke/history (fix_wall_gran.cpp hooke_history()), fix nve/sphere and fix
enforce2d, in the same floating-point operation order as the C++ source. Reruns every deck from its
.data file and compares every dumped x, v, omega, f, torque with LAMMPS (expected: bit for bit).
It also supplies the shear history (LAMMPS cannot dump it) and counts the branches taken.
"""
import math, os, sys, glob
from collections import Counter
# dumpio.py is shared with the granular decks' tools.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from dumpio import read_dump

HERE = os.path.dirname(os.path.abspath(__file__))
DECKS = os.path.join(HERE, "..", "decks")
MY_PI = 3.14159265358979323846
STATS = Counter()
LAST = {}   # branch taken by the latest hooke_history() call: "slip", "slip0" or "stick"


def hooke_history(P, shear, update, dt, delx, dely, delz, rsq, vr, wsum, meff):
    """One contact, returns (fx, fy, fz, tor1, tor2, tor3); updates shear in place.
    delx.. = x_i - x_j (or sphere centre - wall point); vr = v_i - v_j; wsum = R_i w_i + R_j w_j."""
    kn, kt, gamman, gammat, xmu = P["kn"], P["kt"], P["gamman"], P["gammat"], P["xmu"]
    r = math.sqrt(rsq)
    rinv = 1.0 / r
    rsqinv = 1.0 / rsq
    vnnr = vr[0] * delx + vr[1] * dely + vr[2] * delz
    vn1 = delx * vnnr * rsqinv
    vn2 = dely * vnnr * rsqinv
    vn3 = delz * vnnr * rsqinv
    vt1 = vr[0] - vn1
    vt2 = vr[1] - vn2
    vt3 = vr[2] - vn3
    wr1 = wsum[0] * rinv
    wr2 = wsum[1] * rinv
    wr3 = wsum[2] * rinv
    damp = meff * gamman * vnnr * rsqinv
    ccel = kn * (P["radsum"] - r) * rinv - damp
    vtr1 = vt1 - (delz * wr2 - dely * wr3)
    vtr2 = vt2 - (delx * wr3 - delz * wr1)
    vtr3 = vt3 - (dely * wr1 - delx * wr2)
    if update:
        shear[0] += vtr1 * dt
        shear[1] += vtr2 * dt
        shear[2] += vtr3 * dt
    shrmag = math.sqrt(shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2])
    rsht = shear[0] * delx + shear[1] * dely + shear[2] * delz
    rsht *= rsqinv
    if update:
        shear[0] -= rsht * delx
        shear[1] -= rsht * dely
        shear[2] -= rsht * delz
    fs1 = -(kt * shear[0] + meff * gammat * vtr1)
    fs2 = -(kt * shear[1] + meff * gammat * vtr2)
    fs3 = -(kt * shear[2] + meff * gammat * vtr3)
    fs = math.sqrt(fs1 * fs1 + fs2 * fs2 + fs3 * fs3)
    fn = xmu * abs(ccel * r)
    STATS["contact evaluations"] += 1
    if ccel < 0.0:
        STATS["attractive normal force (damping > spring)"] += 1
    if fs > fn:
        if shrmag != 0.0:
            STATS["slip (rescaled)"] += 1
            LAST["branch"] = "slip"
            shear[0] = (fn / fs) * (shear[0] + meff * gammat * vtr1 / kt) - meff * gammat * vtr1 / kt
            shear[1] = (fn / fs) * (shear[1] + meff * gammat * vtr2 / kt) - meff * gammat * vtr2 / kt
            shear[2] = (fn / fs) * (shear[2] + meff * gammat * vtr3 / kt) - meff * gammat * vtr3 / kt
            fs1 *= fn / fs
            fs2 *= fn / fs
            fs3 *= fn / fs
        else:
            STATS["slip with zero shear (fs set to 0)"] += 1
            LAST["branch"] = "slip0"
            fs1 = fs2 = fs3 = 0.0
    else:
        STATS["stick"] += 1
        LAST["branch"] = "stick"
    fx = delx * ccel + fs1
    fy = dely * ccel + fs2
    fz = delz * ccel + fs3
    tor1 = rinv * (dely * fs3 - delz * fs2)
    tor2 = rinv * (delz * fs1 - delx * fs3)
    tor3 = rinv * (delx * fs2 - dely * fs1)
    return (fx, fy, fz, tor1, tor2, tor3)


def parse_hooke(t):
    kn, kt, gn, gt, xmu = (float(v) for v in t[:5])
    if int(t[5]) == 0:
        gt = 0.0
    return dict(kn=kn, kt=kt, gamman=gn, gammat=gt, xmu=xmu)


class Sim:
    def __init__(self, name):
        self.name = name
        self.dim, self.disc, self.enforce2d, self.wall = 3, False, False, None
        for line in open(os.path.join(DECKS, name + ".in")).read().split("\n"):
            t = line.split()
            if not t or t[0].startswith("#"):
                continue
            if t[0] == "dimension":
                self.dim = int(t[1])
            elif t[0] == "pair_style":
                assert t[1] == "gran/hooke/history" and len(t) == 8
                self.pair = parse_hooke(t[2:])
            elif t[0] == "timestep":
                self.dt = float(t[1])
            elif t[0] == "run":
                self.steps = int(t[1])
            elif t[0] == "fix" and t[3] == "nve/sphere":
                self.disc = "disc" in t
            elif t[0] == "fix" and t[3] == "enforce2d":
                self.enforce2d = True
            elif t[0] == "fix" and t[3] == "wall/gran":
                assert t[4] == "hooke/history" and t[11] == "zplane" and t[13] == "NULL"
                self.wall = parse_hooke(t[5:11])
                self.wall_lo = float(t[12])
        self.read_data(os.path.join(DECKS, name + ".data"))
        self.hist = {}
        self.whist = [None] * len(self.atoms)

    def read_data(self, path):
        lines = open(path).read().split("\n")
        i = lines.index("Atoms # sphere") + 2
        self.atoms = []
        while lines[i].strip():
            t = lines[i].split()
            rad = 0.5 * float(t[2])
            rho = float(t[3])
            self.atoms.append(dict(id=int(t[0]), r=rad, rho=rho, m=rho * (4.0 * MY_PI / 3.0 * rad * rad * rad),
                                   x=[float(v) for v in t[4:7]], v=[0.0] * 3, w=[0.0] * 3, f=[0.0] * 3, t=[0.0] * 3))
            i += 1
        i = lines.index("Velocities") + 2
        byid = {a["id"]: a for a in self.atoms}
        while i < len(lines) and lines[i].strip():
            t = lines[i].split()
            byid[int(t[0])]["v"] = [float(v) for v in t[1:4]]
            byid[int(t[0])]["w"] = [float(v) for v in t[4:7]]
            i += 1
        self.atoms.sort(key=lambda a: a["id"])
        self.initial = [dict(id=a["id"], r=a["r"], rho=a["rho"], m=a["m"], x=list(a["x"]), v=list(a["v"]), w=list(a["w"]))
                        for a in self.atoms]

    def forces(self, update):
        A = self.atoms
        self.branch = {}
        for a in A:
            a["f"] = [0.0] * 3
            a["t"] = [0.0] * 3
        # newton off, one rank, no reordering: the half list holds each pair once as (lower id, higher id)
        for i in range(len(A)):
            for j in range(i + 1, len(A)):
                ai, aj = A[i], A[j]
                delx = ai["x"][0] - aj["x"][0]
                dely = ai["x"][1] - aj["x"][1]
                delz = ai["x"][2] - aj["x"][2]
                rsq = delx * delx + dely * dely + delz * delz
                radsum = ai["r"] + aj["r"]
                if rsq >= radsum * radsum:
                    self.hist.pop((i, j), None)
                    continue
                sh = self.hist.setdefault((i, j), [0.0, 0.0, 0.0])
                P = dict(self.pair, radsum=radsum)
                vr = [ai["v"][k] - aj["v"][k] for k in range(3)]
                wsum = [ai["r"] * ai["w"][k] + aj["r"] * aj["w"][k] for k in range(3)]
                meff = ai["m"] * aj["m"] / (ai["m"] + aj["m"])
                fx, fy, fz, t1, t2, t3 = hooke_history(P, sh, update, self.dt, delx, dely, delz, rsq, vr, wsum, meff)
                self.branch[(i, j)] = LAST["branch"]
                ai["f"][0] += fx; ai["f"][1] += fy; ai["f"][2] += fz
                ai["t"][0] -= ai["r"] * t1; ai["t"][1] -= ai["r"] * t2; ai["t"][2] -= ai["r"] * t3
                aj["f"][0] -= fx; aj["f"][1] -= fy; aj["f"][2] -= fz
                aj["t"][0] -= aj["r"] * t1; aj["t"][1] -= aj["r"] * t2; aj["t"][2] -= aj["r"] * t3
        if self.wall:
            for i, a in enumerate(A):
                dz = a["x"][2] - self.wall_lo            # hi = NULL = BIG: del1 < del2 always
                dx = dy = 0.0
                rsq = dx * dx + dy * dy + dz * dz
                if rsq > a["r"] * a["r"]:
                    self.whist[i] = None
                    continue
                if self.whist[i] is None:
                    self.whist[i] = [0.0, 0.0, 0.0]
                P = dict(self.wall, radsum=a["r"])
                vr = [a["v"][k] - 0.0 for k in range(3)]
                wsum = [a["r"] * a["w"][k] for k in range(3)]
                fx, fy, fz, t1, t2, t3 = hooke_history(P, self.whist[i], update, self.dt, dx, dy, dz, rsq, vr, wsum, a["m"])
                self.branch[(i, -1)] = LAST["branch"]
                a["f"][0] += fx; a["f"][1] += fy; a["f"][2] += fz
                a["t"][0] -= a["r"] * t1; a["t"][1] -= a["r"] * t2; a["t"][2] -= a["r"] * t3
        if self.enforce2d:
            for a in A:
                a["v"][2] = 0.0; a["f"][2] = 0.0
                a["w"][0] = a["w"][1] = 0.0
                a["t"][0] = a["t"][1] = 0.0

    def run(self):
        dt = self.dt
        dtf = 0.5 * dt
        dtfrot = dtf / (0.5 if self.disc else 0.4)
        self.forces(update=False)   # setup: no history update
        out = [self.snapshot(0)]
        for step in range(1, self.steps + 1):
            for a in self.atoms:
                dtfm = dtf / a["m"]
                for k in range(3):
                    a["v"][k] += dtfm * a["f"][k]
                for k in range(3):
                    a["x"][k] += dt * a["v"][k]
                dtir = dtfrot / (a["r"] * a["r"] * a["m"])
                for k in range(3):
                    a["w"][k] += dtir * a["t"][k]
            self.forces(update=True)
            for a in self.atoms:
                dtfm = dtf / a["m"]
                for k in range(3):
                    a["v"][k] += dtfm * a["f"][k]
                dtir = dtfrot / (a["r"] * a["r"] * a["m"])
                for k in range(3):
                    a["w"][k] += dtir * a["t"][k]
            out.append(self.snapshot(step))
        return out

    def snapshot(self, step):
        atoms = [a["x"] + a["v"] + a["w"] + a["f"] + a["t"] for a in self.atoms]
        # {(id_i, id_j or 0 for the wall): (shear history after the step, branch taken this step)}
        hist = {(self.atoms[i]["id"], self.atoms[j]["id"]): (list(h), self.branch[(i, j)]) for (i, j), h in self.hist.items()}
        for i, h in enumerate(self.whist):
            if h is not None:
                hist[(self.atoms[i]["id"], 0)] = (list(h), self.branch[(i, -1)])
        return (step, atoms, hist)


FIELDS = ["x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz", "fx", "fy", "fz", "tqx", "tqy", "tqz"]


def compare(name):
    """Largest |python - lammps| relative to the field group's largest magnitude; also exact-bit mismatches."""
    sim = Sim(name)
    ref = sim.run()
    dump = read_dump(os.path.join(DECKS, "out", name + ".dump"))
    group = lambda f: f[:-1] if f.startswith(("omega", "tq")) else ("x" if f in "xyz" else f[0])
    scale = {}
    for step, cols, rows in dump:
        c = {k: i for i, k in enumerate(cols)}
        for row in rows:
            for fld in FIELDS:
                scale[group(fld)] = max(scale.get(group(fld), 0.0), abs(float(row[c[fld]])))
    worst, where, nbits = 0.0, None, 0
    assert len(ref) == len(dump)
    for (step, atoms, _), (dstep, cols, rows) in zip(ref, dump):
        assert step == dstep
        c = {k: i for i, k in enumerate(cols)}
        for a, row in zip(atoms, rows):
            for fi, fld in enumerate(FIELDS):
                lv = float(row[c[fld]])
                if a[fi] != lv:
                    nbits += 1
                d = abs(a[fi] - lv) / scale[group(fld)] if scale[group(fld)] else 0.0
                if d > worst:
                    worst, where = d, (step, row[0], fld, a[fi], lv)
    return worst, where, nbits, sim, ref


if __name__ == "__main__":
    names = sys.argv[1:] or sorted(os.path.basename(p)[:-3] for p in glob.glob(os.path.join(DECKS, "*.in")))
    for nm in names:
        STATS.clear()
        w, where, nbits, _, _ = compare(nm)
        print(f"{nm}: max |python - lammps| / max|field| = {w:.3e} ({nbits} values not bit-identical) at {where}")
        print("    branches:", dict(sorted(STATS.items())))
