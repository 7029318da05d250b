#!/usr/bin/env python3
"""Independent re-implementation of SPEC.md (LAMMPS 29Sep2021 pair granular, fix wall/gran granular,
fix nve/sphere, fix enforce2d) in plain Python, run on each deck's data file and compared with
the LAMMPS per-step dump. It exists to check SPEC.md, and as a readable reference for the Rust port.

Usage: python3 tools/ref_granular.py [deck-name ...]   (default: every deck in decks/)
Prints, per deck, the largest relative difference over all steps and fields.
"""
import math, os, sys, glob

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dumpio import read_dump

HERE = os.path.dirname(os.path.abspath(__file__))
DECKS = os.path.join(HERE, "..", "decks")
FOURTHIRDS = 4.0 / 3.0
TWOTHIRDS = 2.0 / 3.0
EPSILON = 1e-10
MY_PI = 3.14159265358979323846
STATS = {}  # counts of branch events (for the README coverage table)


def _count(k):
    STATS[k] = STATS.get(k, 0) + 1


def powint(x, n):
    if x == 0.0:
        return 0.0
    yy, ww, nn = 1.0, x, n
    while nn != 0:
        if nn & 1:
            yy *= ww
        nn >>= 1
        ww *= ww
    return yy


def tsuji_alpha(cor):
    # pair_granular.cpp:990 (same in fix_wall_gran.cpp)
    return (1.2728 - 4.2783 * cor + 11.087 * (cor * cor) - 22.348 * (cor * cor * cor)
            + 27.467 * powint(cor, 4) - 18.022 * powint(cor, 5) + 4.8218 * powint(cor, 6))


def mix_E(Ei, Ej, ni, nj):
    return 1 / ((1 - ni * ni) / Ei + (1 - nj * nj) / Ej)


def mix_G(Ei, Ej, ni, nj):
    return 1 / ((2 * (2 - ni) * (1 + ni) / Ei) + (2 * (2 - nj) * (1 + nj) / Ej))


def parse_law(tok, wall=False):
    """Parse the model keywords of a pair_coeff (after the types) or of fix wall/gran granular."""
    law = dict(damping="viscoelastic", roll=None, twist=None, limit_damping=False)
    i = 0
    while i < len(tok):
        t = tok[i]
        if t in ("hooke", "hertz"):
            law["normal"] = t
            law["kn"] = float(tok[i + 1]); law["damp_in"] = float(tok[i + 2]); i += 3
        elif t == "hertz/material":
            law["normal"] = t
            E, nu = float(tok[i + 1]), float(tok[i + 3])
            law["E"], law["nu"], law["damp_in"] = E, nu, float(tok[i + 2])
            if wall:  # fix_wall_gran.cpp:160, note (1-nu), not (1-nu^2)
                law["kn"] = E / (2 * (1 - nu)) * 1.333333333333333  # macro FOURTHIRDS, 16 digits
            else:     # pair_granular.cpp:1009
                law["kn"] = FOURTHIRDS * mix_E(E, E, nu, nu)
            i += 4
        elif t == "damping":
            law["damping"] = tok[i + 1]; i += 2
        elif t == "tangential":
            law["tangential"] = tok[i + 1]
            if tok[i + 1] == "linear_nohistory":
                law["kt"] = 0.0; law["xgt"] = float(tok[i + 2]); law["mu"] = float(tok[i + 3]); i += 4
            else:
                if tok[i + 2] == "NULL":
                    E, nu = law["E"], law["nu"]
                    law["kt"] = (E / 4 * (2 - nu) * (1 + nu)) if wall else 8 * mix_G(E, E, nu, nu)
                else:
                    law["kt"] = float(tok[i + 2])
                law["xgt"] = float(tok[i + 3]); law["mu"] = float(tok[i + 4]); i += 5
        elif t == "rolling":
            if tok[i + 1] == "sds":
                law["roll"] = (float(tok[i + 2]), float(tok[i + 3]), float(tok[i + 4])); i += 5
            else:
                i += 2
        elif t == "twisting":
            if tok[i + 1] == "marshall":
                law["twist"] = "marshall"; i += 2
            elif tok[i + 1] == "sds":
                law["twist"] = (float(tok[i + 2]), float(tok[i + 3]), float(tok[i + 4])); i += 5
            else:
                i += 2
        elif t == "limit_damping":
            law["limit_damping"] = True; i += 1
        elif t in ("xplane", "yplane", "zplane"):
            law["wall"] = (t, float(tok[i + 1])); i += 3
        else:
            raise ValueError("unsupported keyword " + t)
    law["damp"] = tsuji_alpha(law["damp_in"]) if law["damping"] == "tsuji" else law["damp_in"]
    th = law["tangential"] != "linear_nohistory"
    rescale = law["tangential"].startswith("mindlin_rescale")
    # history layout (pair_granular.cpp:1081-1111): [t0 t1 t2 (a_prev)] [r0 r1 r2] [tw]
    law["ti"] = 0
    law["ri"] = (3 if th else 0) + (1 if rescale else 0)
    law["twi"] = law["ri"] + (3 if law["roll"] else 0)
    law["nhist"] = law["twi"] + (1 if law["twist"] else 0)
    return law


def contact(law, hist, dt, update, n, delta, Reff, meff, vr, wr, relrot, rad_i_arm, rad_j_arm):
    """One contact, in the order of PairGranular::compute (pair_granular.cpp:290-707).
    n: unit normal from j to i; vr = v_i - v_j; wr = R_i w_i + R_j w_j (pair) or R_i w_i (wall);
    relrot = w_i - w_j. Returns (F on i, torque on i, torque on j (None for wall))."""
    nx, ny, nz = n
    vr1, vr2, vr3 = vr
    vnnr = vr1 * nx + vr2 * ny + vr3 * nz
    vn1, vn2, vn3 = nx * vnnr, ny * vnnr, nz * vnnr
    dR = delta * Reff
    knfac = law["kn"]
    Fne = knfac * delta
    a = math.sqrt(dR)
    if law["normal"] != "hooke":
        Fne *= a
        knfac *= a
    dm = law["damping"]
    if dm == "velocity":
        damp_normal = 1
    elif dm == "mass_velocity":
        damp_normal = meff
    elif dm == "viscoelastic":
        damp_normal = a * meff
    elif dm == "tsuji":
        damp_normal = math.sqrt(meff * knfac)
    damp_normal_prefactor = law["damp"] * damp_normal
    Fdamp = -damp_normal_prefactor * vnnr
    Fntot = Fne + Fdamp
    if Fntot < 0.0:
        _count("Fn_negative")
    if law["limit_damping"] and Fntot < 0.0:
        Fntot = 0.0
    vt1, vt2, vt3 = vr1 - vn1, vr2 - vn2, vr3 - vn3
    wr1, wr2, wr3 = wr
    vtr1 = vt1 - (nz * wr2 - ny * wr3)
    vtr2 = vt2 - (nx * wr3 - nz * wr1)
    vtr3 = vt3 - (ny * wr1 - nx * wr2)
    vrel = math.sqrt(vtr1 * vtr1 + vtr2 * vtr2 + vtr3 * vtr3)
    Fncrit = abs(Fntot)
    Fscrit = law["mu"] * Fncrit
    k_t = law["kt"]
    damp_t = law["xgt"] * damp_normal_prefactor
    tm = law["tangential"]
    h = hist
    if tm != "linear_nohistory":
        force_form = tm.endswith("/force")
        if tm.startswith("mindlin"):
            k_t *= a
            if tm.startswith("mindlin_rescale"):
                if a < h[3]:
                    _count("rescale")
                    factor = a / h[3]
                    h[0] *= factor; h[1] *= factor; h[2] *= factor
        if update:
            rsht = h[0] * nx + h[1] * ny + h[2] * nz
            frameupdate = abs(rsht) > EPSILON * Fscrit if force_form else abs(rsht) * k_t > EPSILON * Fscrit
            if frameupdate:
                _count("t_project")
                shrmag = math.sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2])
                h[0] -= rsht * nx; h[1] -= rsht * ny; h[2] -= rsht * nz
                prjmag = math.sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2])
                scalefac = shrmag / prjmag if prjmag > 0 else 0
                h[0] *= scalefac; h[1] *= scalefac; h[2] *= scalefac
            if not force_form:
                h[0] += vtr1 * dt; h[1] += vtr2 * dt; h[2] += vtr3 * dt
            else:
                h[0] -= k_t * vtr1 * dt; h[1] -= k_t * vtr2 * dt; h[2] -= k_t * vtr3 * dt
            if tm.startswith("mindlin_rescale"):
                h[3] = a
        if not force_form:
            fs1 = -k_t * h[0] - damp_t * vtr1
            fs2 = -k_t * h[1] - damp_t * vtr2
            fs3 = -k_t * h[2] - damp_t * vtr3
        else:
            fs1 = h[0] - damp_t * vtr1; fs2 = h[1] - damp_t * vtr2; fs3 = h[2] - damp_t * vtr3
        fs = math.sqrt(fs1 * fs1 + fs2 * fs2 + fs3 * fs3)
        if fs > Fscrit:
            _count("slip")
            shrmag = math.sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2])
            if shrmag != 0.0:
                if not force_form:
                    h[0] = -1.0 / k_t * (Fscrit * fs1 / fs + damp_t * vtr1)
                    h[1] = -1.0 / k_t * (Fscrit * fs2 / fs + damp_t * vtr2)
                    h[2] = -1.0 / k_t * (Fscrit * fs3 / fs + damp_t * vtr3)
                else:
                    h[0] = Fscrit * fs1 / fs + damp_t * vtr1
                    h[1] = Fscrit * fs2 / fs + damp_t * vtr2
                    h[2] = Fscrit * fs3 / fs + damp_t * vtr3
                fs1 *= Fscrit / fs; fs2 *= Fscrit / fs; fs3 *= Fscrit / fs
            else:
                fs1 = fs2 = fs3 = 0.0
    else:
        fs = damp_t * vrel
        Ft = min(Fscrit, fs) / vrel if vrel != 0.0 else 0.0
        fs1, fs2, fs3 = -Ft * vtr1, -Ft * vtr2, -Ft * vtr3
    r1, r2, r3 = relrot
    if law["roll"]:
        vrl1 = Reff * (r2 * nz - r3 * ny)
        vrl2 = Reff * (r3 * nx - r1 * nz)
        vrl3 = Reff * (r1 * ny - r2 * nx)
        ri = law["ri"]
        k_roll, damp_roll, mur = law["roll"]
        Frcrit = mur * Fncrit
        if update:
            rolldotn = h[ri] * nx + h[ri + 1] * ny + h[ri + 2] * nz
            if abs(rolldotn) * k_roll > EPSILON * Frcrit:
                rollmag = math.sqrt(h[ri] ** 2 + h[ri + 1] ** 2 + h[ri + 2] ** 2)
                h[ri] -= rolldotn * nx; h[ri + 1] -= rolldotn * ny; h[ri + 2] -= rolldotn * nz
                prjmag = math.sqrt(h[ri] * h[ri] + h[ri + 1] * h[ri + 1] + h[ri + 2] * h[ri + 2])
                scalefac = rollmag / prjmag if prjmag > 0 else 0
                h[ri] *= scalefac; h[ri + 1] *= scalefac; h[ri + 2] *= scalefac
            h[ri] += vrl1 * dt; h[ri + 1] += vrl2 * dt; h[ri + 2] += vrl3 * dt
        fr1 = -k_roll * h[ri] - damp_roll * vrl1
        fr2 = -k_roll * h[ri + 1] - damp_roll * vrl2
        fr3 = -k_roll * h[ri + 2] - damp_roll * vrl3
        fr = math.sqrt(fr1 * fr1 + fr2 * fr2 + fr3 * fr3)
        if fr > Frcrit:
            _count("roll_slip")
            rollmag = math.sqrt(h[ri] * h[ri] + h[ri + 1] * h[ri + 1] + h[ri + 2] * h[ri + 2])
            if rollmag != 0.0:
                h[ri] = -1.0 / k_roll * (Frcrit * fr1 / fr + damp_roll * vrl1)
                h[ri + 1] = -1.0 / k_roll * (Frcrit * fr2 / fr + damp_roll * vrl2)
                h[ri + 2] = -1.0 / k_roll * (Frcrit * fr3 / fr + damp_roll * vrl3)
                fr1 *= Frcrit / fr; fr2 *= Frcrit / fr; fr3 *= Frcrit / fr
            else:
                fr1 = fr2 = fr3 = 0.0
    if law["twist"]:
        magtwist = r1 * nx + r2 * ny + r3 * nz
        if law["twist"] == "marshall":
            k_twist = 0.5 * k_t * a * a
            damp_twist = 0.5 * damp_t * a * a
            mu_twist = TWOTHIRDS * a * law["mu"]
        else:
            k_twist, damp_twist, mu_twist = law["twist"]
        twi = law["twi"]
        if update:
            h[twi] += magtwist * dt
        magtortwist = -k_twist * h[twi] - damp_twist * magtwist
        signtwist = (magtwist > 0) - (magtwist < 0)
        Mtcrit = mu_twist * Fncrit
        if abs(magtortwist) > Mtcrit:
            _count("twist_slip")
            h[twi] = 1.0 / k_twist * (Mtcrit * signtwist - damp_twist * magtwist)
            magtortwist = -Mtcrit * signtwist
    _count("contact")
    F = (nx * Fntot + fs1, ny * Fntot + fs2, nz * Fntot + fs3)
    tor1 = ny * fs3 - nz * fs2
    tor2 = nz * fs1 - nx * fs3
    tor3 = nx * fs2 - ny * fs1
    # torque accumulation mirrors the += order in the C++ (tangential, twist, roll)
    ti = [-rad_i_arm * tor1, -rad_i_arm * tor2, -rad_i_arm * tor3]
    tj = None if rad_j_arm is None else [-rad_j_arm * tor1, -rad_j_arm * tor2, -rad_j_arm * tor3]
    extra_i = []
    if law["twist"]:
        extra_i.append((magtortwist * nx, magtortwist * ny, magtortwist * nz))
    if law["roll"]:
        extra_i.append((Reff * (ny * fr3 - nz * fr2), Reff * (nz * fr1 - nx * fr3), Reff * (nx * fr2 - ny * fr1)))
    return F, (tor1, tor2, tor3), extra_i


class Sim:
    def __init__(self, name):
        self.name = name
        deck = open(os.path.join(DECKS, name + ".in")).read().split("\n")
        self.dim = 3
        self.laws = {}
        self.wall = None
        self.disc = False
        self.enforce2d = False
        for line in deck:
            t = line.split()
            if not t or t[0].startswith("#"):
                continue
            if t[0] == "dimension":
                self.dim = int(t[1])
            elif t[0] == "pair_coeff":
                assert t[1] == "*" or t[2] != "*"
                key = "*" if t[1] == "*" else (int(t[1]), int(t[2]))
                self.laws[key] = parse_law(t[3:])
            elif t[0] == "timestep":
                self.dt = float(t[1])
            elif t[0] == "run":
                self.steps = int(t[1])
            elif t[0] == "fix" and t[3] == "nve/sphere":
                self.disc = "disc" in t
            elif t[0] == "fix" and t[3] == "enforce2d":
                self.enforce2d = True
            elif t[0] == "fix" and t[3] == "wall/gran":
                assert t[4] == "granular"
                self.wall = parse_law(t[5:], wall=True)
        self.read_data(os.path.join(DECKS, name + ".data"))
        self.hist = {}
        self.whist = [None] * len(self.atoms)

    def law(self, ti, tj):
        if "*" in self.laws:
            return self.laws["*"]
        return self.laws.get((min(ti, tj), max(ti, tj)))

    def read_data(self, path):
        lines = open(path).read().split("\n")
        i = lines.index("Atoms # sphere") + 2
        self.atoms = []
        while lines[i].strip():
            t = lines[i].split()
            rad = 0.5 * float(t[2])
            mass = float(t[3]) * (4.0 * MY_PI / 3.0 * rad * rad * rad)
            self.atoms.append(dict(id=int(t[0]), type=int(t[1]), r=rad, m=mass,
                                   x=[float(v) for v in t[4:7]], v=[0.0] * 3, w=[0.0] * 3,
                                   f=[0.0] * 3, t=[0.0] * 3))
            i += 1
        i = lines.index("Velocities") + 2
        byid = {a["id"]: a for a in self.atoms}
        while i < len(lines) and lines[i].strip():
            t = lines[i].split()
            a = byid[int(t[0])]
            a["v"] = [float(v) for v in t[1:4]]
            a["w"] = [float(v) for v in t[4:7]]
            i += 1
        self.atoms.sort(key=lambda a: a["id"])

    def forces(self, update):
        A = self.atoms
        for a in A:
            a["f"] = [0.0] * 3
            a["t"] = [0.0] * 3
        for i in range(len(A)):
            for j in range(i + 1, len(A)):
                ai, aj = A[i], A[j]
                law = self.law(ai["type"], aj["type"])
                d = [ai["x"][k] - aj["x"][k] for k in range(3)]
                rsq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
                radsum = ai["r"] + aj["r"]
                if rsq >= radsum * radsum:
                    self.hist.pop((i, j), None)
                    continue
                h = self.hist.setdefault((i, j), [0.0] * law["nhist"])
                r = math.sqrt(rsq)
                rinv = 1.0 / r
                n = (d[0] * rinv, d[1] * rinv, d[2] * rinv)
                vr = [ai["v"][k] - aj["v"][k] for k in range(3)]
                mi, mj = ai["m"], aj["m"]
                meff = mi * mj / (mi + mj)
                delta = radsum - r
                Reff = ai["r"] * aj["r"] / radsum
                wr = [ai["r"] * ai["w"][k] + aj["r"] * aj["w"][k] for k in range(3)]
                relrot = [ai["w"][k] - aj["w"][k] for k in range(3)]
                F, tor, extra = contact(law, h, self.dt, update, n, delta, Reff, meff, vr, wr, relrot, 0, 0)
                arm_i = ai["r"] - 0.5 * delta
                arm_j = aj["r"] - 0.5 * delta
                for k in range(3):
                    ai["f"][k] += F[k]
                for k in range(3):
                    ai["t"][k] -= arm_i * tor[k]
                for e in extra:
                    for k in range(3):
                        ai["t"][k] += e[k]
                for k in range(3):
                    aj["f"][k] -= F[k]
                for k in range(3):
                    aj["t"][k] -= arm_j * tor[k]
                for e in extra:
                    for k in range(3):
                        aj["t"][k] -= e[k]
        if self.wall:
            law = self.wall
            axis = "xyz".index(law["wall"][0][0])
            lo = law["wall"][1]
            for i, a in enumerate(A):
                dx = [0.0, 0.0, 0.0]
                dx[axis] = a["x"][axis] - lo   # hi = NULL (BIG): del1 < del2 always
                rsq = dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]
                if rsq > a["r"] * a["r"]:
                    self.whist[i] = None
                    continue
                if self.whist[i] is None:
                    self.whist[i] = [0.0] * law["nhist"]
                r = math.sqrt(rsq)
                rinv = 1.0 / r
                n = (dx[0] * rinv, dx[1] * rinv, dx[2] * rinv)
                delta = a["r"] - r
                F, tor, extra = contact(law, self.whist[i], self.dt, update, n, delta, a["r"], a["m"],
                                        list(a["v"]), [a["r"] * a["w"][k] for k in range(3)], list(a["w"]), 0, None)
                for k in range(3):
                    a["f"][k] += F[k]
                for k in range(3):
                    a["t"][k] -= a["r"] * tor[k]
                for e in extra:
                    for k in range(3):
                        a["t"][k] += e[k]
        if self.enforce2d:
            for a in A:
                a["v"][2] = 0.0; a["f"][2] = 0.0
                a["w"][0] = a["w"][1] = 0.0
                a["t"][0] = a["t"][1] = 0.0

    def run(self):
        dt = self.dt
        dtf = 0.5 * dt
        dtfrot = dtf / (0.5 if self.disc else 0.4)
        self.forces(update=False)   # setup: forces without history update
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
        """(step, per-atom [x v w f t] lists in id order, {(id_i, id_j or 0 for the wall): history copy})."""
        atoms = [a["x"] + a["v"] + a["w"] + a["f"] + a["t"] for a in self.atoms]
        hist = {(self.atoms[i]["id"], self.atoms[j]["id"]): list(h) for (i, j), h in self.hist.items()}
        for i, h in enumerate(self.whist):
            if h is not None:
                hist[(self.atoms[i]["id"], 0)] = list(h)
        return (step, atoms, hist)


FIELDS = ["x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz", "fx", "fy", "fz", "tqx", "tqy", "tqz"]


def compare(name):
    sim = Sim(name)
    ref = sim.run()
    dump = read_dump(os.path.join(DECKS, "out", name + ".dump"))
    worst = 0.0
    where = None
    # per field group, relative to the group's largest magnitude over the run (forces are 0 off contact)
    scale = {}
    for step, cols, rows in dump:
        c = {k: i for i, k in enumerate(cols)}
        for row in rows:
            for fi, fld in enumerate(FIELDS):
                g = fld[:-1] if fld.startswith(("omega", "tq")) else ("x" if fld in "xyz" else fld[0])
                scale[g] = max(scale.get(g, 0.0), abs(float(row[c[fld]])))
    for (step, atoms, _), (dstep, cols, rows) in zip(ref, dump):
        assert step == dstep
        c = {k: i for i, k in enumerate(cols)}
        for a, row in zip(atoms, rows):
            for fi, fld in enumerate(FIELDS):
                g = fld[:-1] if fld.startswith(("omega", "tq")) else ("x" if fld in "xyz" else fld[0])
                lv = float(row[c[fld]])
                d = abs(a[fi] - lv) / scale[g]
                if d > worst:
                    worst, where = d, (step, row[0], fld, a[fi], lv)
    return worst, where, sim, ref


if __name__ == "__main__":
    names = sys.argv[1:] or sorted(os.path.basename(p)[:-3] for p in glob.glob(os.path.join(DECKS, "*.in")))
    for nm in names:
        STATS.clear()
        w, where, _, _ = compare(nm)
        print(f"{nm}: max |python - lammps| / max|field| = {w:.3e}  at {where}")
        print("    contact evaluations and branches taken:", dict(sorted(STATS.items())))
