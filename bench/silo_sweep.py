#!/usr/bin/env python3
"""Silo discharge against orifice size (VALIDATION.md, "Silo discharge"): runs
examples/dem3d/silo_small.toml widened to a 25 mm silo with orifices of D = 4, 4.5, 5 and
6 mean diameters (the fill scaled with the silo), or with --full examples/dem3d/silo.toml
(a 40 mm silo, 7500 spheres) with D = 4, 5, 6 and 7 mean diameters, reads each run's steady mass flow rate
W from summary.json, and fits Beverloo's W = C rho_b sqrt(g) (D - k d)^(5/2) by least
squares on W^(2/5) = a D + b (a = (C rho_b sqrt g)^(2/5), k = -b / (a d)). rho_b is the
bed's packing as measured above the orifice (the runs' mean) times the grains' density
where every run measured it (the silo is deep enough), else the example's `packing`.
Writes OUT.csv (columns D_over_d, orifice_m, rate_kg_s, c_at_k1.5, packing_measured,
c_at_k1.5_measured, and a last line with the fit) and prints the fitted C and k. With
--from-work the runs already in WORK_DIR are read again and nothing is run.

usage: python3 bench/silo_sweep.py GRAINS_BINARY OUT.csv [WORK_DIR] [--full] [--from-work]
No dependencies beyond the standard library; each run takes 30-60 s on 2 cores (--full:
a few minutes).
"""
import json
import math
import os
import re
import sys
import tempfile

from sweep_run import run

args = [a for a in sys.argv[1:] if a not in ('--full', '--from-work')]
full = '--full' in sys.argv[1:]
from_work = '--from-work' in sys.argv[1:]
grains, out = args[0:2]
if from_work and len(args) < 3:
    sys.exit('silo_sweep.py: --from-work reads the runs in WORK_DIR: name it (GRAINS_BINARY is not used then)')
work = args[2] if len(args) > 2 else tempfile.mkdtemp()
here = os.path.dirname(os.path.abspath(__file__))
examples = os.path.join(here, '..', 'examples', 'dem3d')
if full:
    SIZES = [4, 5, 6, 7]
    base = open(os.path.join(examples, 'silo.toml')).read()
else:
    SIZES = [4, 4.5, 5, 6]
    base = open(os.path.join(examples, 'silo_small.toml')).read()
    # The wider silo: radius 25 mm, domain and fill to match (1.56x the cross-section).
    base = base.replace('radius = 0.02\n', 'radius = 0.025\n')
    base = base.replace('[-0.021, -0.021,', '[-0.026, -0.026,').replace('[0.021, 0.021,', '[0.026, 0.026,')
    base = base.replace('radius = 0.0195, height', 'radius = 0.0245, height')
    base = base.replace('count = 900', 'count = 1400')
rows = []
for k in SIZES:
    name = f'silo{"_full" if full else ""}_D{k}d'
    text = re.sub(r'(?m)^hole = .*$', f'hole = {k * 0.00195 * 2 / 2}', base)
    if from_work:
        f = json.load(open(os.path.join(work, name, 'summary.json')))['figures']
    else:
        f = run(grains, text, work, name)['figures']
    g = lambda key: f.get('mass_flow_rate_' + key)
    c, c_measured = g('c_at_k1.5'), g('c_at_k1.5_measured')
    rho_measured = g('bulk_density_measured')
    rows.append((k, g('orifice_m'), g('rate_kg_s'), c, g('mean_diameter_m'), g('bulk_density'),
                 g('packing_measured'), c_measured, rho_measured))
    print(f'D = {k} d = {rows[-1][1] * 1e3:.2f} mm: W = {rows[-1][2] * 1e3:.3f} g/s, C at k = 1.5: {c:.3f}'
          + (f' ({c_measured:.3f} at the measured packing {g("packing_measured"):.3f})' if c_measured else ''))
d = rows[0][4]
measured = all(r[8] for r in rows)
rho_b = sum(r[8] for r in rows) / len(rows) if measured else rows[0][5]
xs = [r[1] for r in rows]
ys = [r[2] ** 0.4 for r in rows]
n = len(xs)
mx, my = sum(xs) / n, sum(ys) / n
a = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
b = my - a * mx
c_fit = a ** 2.5 / (rho_b * math.sqrt(9.81))
k_fit = -b / (a * d)
with open(out, 'w') as fo:
    fo.write('D_over_d,orifice_m,rate_kg_s,c_at_k1.5,packing_measured,c_at_k1.5_measured\n')
    for r in rows:
        extra = f'{r[6]:.4f},{r[7]:.4f}' if r[7] else ','
        fo.write(f'{r[0]},{r[1]:.6f},{r[2]:.6f},{r[3]:.4f},{extra}\n')
    fo.write(f'# fit: C = {c_fit:.4f}, k = {k_fit:.3f} (d = {d:.6f} m, rho_b = {rho_b:.1f} kg/m3, '
             f'{"measured" if measured else "assumed"})\n')
print(f'Beverloo fit: C = {c_fit:.3f}, k = {k_fit:.2f}  (literature C 0.55-0.65, k 1.3-2.9)')
