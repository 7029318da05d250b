#!/usr/bin/env python3
"""An independent figure for the bouncing cylinder's restitution (bardenhagen-1998 Fig. 2;
VALIDATION.md "Bounce restitution"): the same elastic disk (radius 0.5, rho 1, K 1, G 0.5,
plane strain) hitting a rigid frictionless wall at 0.1 normal to it, computed by explicit
finite elements instead of MPM. Linear triangles on rings of 6k nodes, lumped masses,
central differences, the wall as a stiff penalty spring on each node (elastic, so the
contact itself keeps energy). The normal restitution is the centre of mass's normal
velocity after the disk leaves the wall over the one before. A frictionless wall does not
couple the tangential motion, so only the normal approach is simulated.

usage: python3 bench/bounce_fem_reference.py [RINGS ...] [--penalty P]
needs numpy.
"""
import argparse
import math
import time

import numpy as np

R, RHO, K, G, V = 0.5, 1.0, 1.0, 0.5, 0.1
LAM = K - 2.0 * G / 3.0  # plane strain with the 3D bulk modulus, as grains' MPM


def disk_mesh(n):
    """Nodes on rings r = R k / n (6k nodes on ring k) and the triangles between rings."""
    pts = [(0.0, 0.0)]
    rings = [[0]]
    for k in range(1, n + 1):
        m = 6 * k
        idx = []
        for j in range(m):
            a = 2 * math.pi * j / m
            idx.append(len(pts))
            pts.append((R * k / n * math.cos(a), R * k / n * math.sin(a)))
        rings.append(idx)
    tris = []
    for k in range(n):
        inner, outer = rings[k], rings[k + 1]
        if k == 0:
            for j in range(6):
                tris.append((0, outer[j], outer[(j + 1) % 6]))
            continue
        mi, mo = len(inner), len(outer)
        i = o = 0
        # zip the two rings by angle, one triangle per step
        while i < mi or o < mo:
            ai = (i + 0.5) / mi if i < mi else 2.0
            ao = (o + 0.5) / mo if o < mo else 2.0
            if ao <= ai:
                tris.append((inner[i % mi], outer[o % mo], outer[(o + 1) % mo]))
                o += 1
            else:
                tris.append((inner[i % mi], outer[o % mo], inner[(i + 1) % mi]))
                i += 1
    return np.array(pts), np.array(tris), np.array(rings[-1])


def run(n, penalty):
    x0, tri, rim = disk_mesh(n)
    nn = len(x0)
    p = x0[tri]  # (ne, 3, 2)
    b = np.stack([p[:, 1, 1] - p[:, 2, 1], p[:, 2, 1] - p[:, 0, 1], p[:, 0, 1] - p[:, 1, 1]], 1)
    c = np.stack([p[:, 2, 0] - p[:, 1, 0], p[:, 0, 0] - p[:, 2, 0], p[:, 1, 0] - p[:, 0, 0]], 1)
    area = 0.5 * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0])
    assert (area > 0).all(), "mesh orientation"
    dNx, dNy = b / (2 * area[:, None]), c / (2 * area[:, None])
    mass = np.bincount(tri.ravel(), np.repeat(RHO * area / 3.0, 3), nn)
    total = mass.sum()
    h = R / n
    e_mod = 9 * K * G / (3 * K + G)
    k_wall = penalty * e_mod  # per node: the node's stiffness in the body is ~E per unit thickness
    cp = math.sqrt((K + 4 * G / 3) / RHO)
    dt = min(0.25 * h / cp, 0.2 * math.sqrt(mass[rim].min() / k_wall))
    # start touching, moving into the wall y = R at +V
    u = np.zeros((nn, 2))
    v = np.zeros((nn, 2))
    v[:, 1] = V
    wall = R

    def forces(u):
        ux, uy = u[tri, 0], u[tri, 1]
        exx = (dNx * ux).sum(1)
        eyy = (dNy * uy).sum(1)
        gxy = (dNy * ux).sum(1) + (dNx * uy).sum(1)
        tr = exx + eyy
        sxx = LAM * tr + 2 * G * exx
        syy = LAM * tr + 2 * G * eyy
        sxy = G * gxy
        fx = -(area[:, None] * (dNx * sxx[:, None] + dNy * sxy[:, None]))
        fy = -(area[:, None] * (dNx * sxy[:, None] + dNy * syy[:, None]))
        f = np.empty((nn, 2))
        f[:, 0] = np.bincount(tri.ravel(), fx.ravel(), nn)
        f[:, 1] = np.bincount(tri.ravel(), fy.ravel(), nn)
        y = x0[rim, 1] + u[rim, 1]
        pen = np.maximum(y - wall, 0.0)
        f[rim, 1] -= k_wall * pen
        return f, pen

    f, pen = forces(u)
    t, left, steps = 0.0, None, 0
    max_pen = 0.0
    t0 = time.time()
    while True:
        v += 0.5 * dt * f / mass[:, None]
        u += dt * v
        f, pen = forces(u)
        v += 0.5 * dt * f / mass[:, None]
        t += dt
        steps += 1
        max_pen = max(max_pen, pen.max())
        touching = (pen > 0).any()
        if not touching and left is None and t > 0.1:
            left = t
        if touching:
            left = None
        # momentum is constant once no node touches: wait a while to be sure it stays off
        if left is not None and t - left > 2.0:
            break
        if t > 40:
            raise SystemExit("no separation by t = 40")
    vcm = (mass * v[:, 1]).sum() / total
    ke_cm = 0.5 * total * vcm ** 2
    return dict(rings=n, nodes=nn, h=h, steps=steps, contact_time=left, restitution=-vcm / V,
                max_penetration_over_h=max_pen / h, wall=time.time() - t0,
                ke_total=0.5 * (mass[:, None] * v ** 2).sum(), ke_cm=ke_cm, ke0=0.5 * total * V ** 2)


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("rings", nargs="*", type=int, default=[16, 32, 64])
    ap.add_argument("--penalty", type=float, default=20.0)
    a = ap.parse_args()
    print("rings,nodes,h,steps,contact_time,restitution,max_penetration_over_h,wall_s")
    for n in a.rings:
        r = run(n, a.penalty)
        print(f"{r['rings']},{r['nodes']},{r['h']:.5g},{r['steps']},{r['contact_time']:.5f},"
              f"{r['restitution']:.6f},{r['max_penetration_over_h']:.4f},{r['wall']:.1f}", flush=True)
