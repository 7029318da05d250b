#!/usr/bin/env python3
"""Column collapse: run-out against aspect ratio beside Lube et al. (J. Fluid Mech. 508,
2004) (VALIDATION.md, "Column collapse"). Runs examples/dem3d/collapse_small.toml with
columns of COUNTS spheres (the same tube, R0 = 20 mm = 5 d; the fill's height, the
release time and the duration grown with the count), reads each run's figures from its
summary.json, runs examples/dem3d/collapse.toml as it is (R0 = 30 mm = 7.5 d: the
same column 1.5 times wider in grains), and writes OUT.csv (columns count,
aspect_ratio, h0_m, r0_m, r_inf_m, edge_m, front_m, runout, runout_edge, lube, r0_over_d:
r_inf_m is the radius holding 99 % of the spheres' edges the check takes, edge_m the
edge of the continuous deposit, a figure beside it, runout and runout_edge their
(R - R0)/R0). Then
`cargo run -p grains-sim --example collapse_runout -- OUT.csv` draws OUT.png.

With --wide, also `collapse.toml` scaled 1.5 and 2 times (R0/d = 11.25 and 15, 13 k and
31 k spheres, the fill, domain, release and duration grown with it): 7 and 20 min more
on one core.

usage: python3 bench/collapse_sweep.py GRAINS_BINARY OUT.csv [WORK_DIR] [--wide]
No dependencies beyond the standard library; the five runs take about 2 min on 2 cores.
"""
import math
import os
import re
import sys
import tempfile

from sweep_run import run

COUNTS = [180, 480, 760, 1140]
# Height of tube each sphere's random place takes (m): the fill's solid fraction is 0.26.
PER_SPHERE = 0.045 / 480

wide = '--wide' in sys.argv
args = [a for a in sys.argv[1:] if a != '--wide']
grains, out = args[:2]
work = args[2] if len(args) > 2 else tempfile.mkdtemp()
here = os.path.dirname(os.path.abspath(__file__))
base = open(os.path.join(here, '..', 'examples', 'dem3d', 'collapse_small.toml')).read()
D = 0.004
rows = []


def record(n, summary):
    f = summary['figures']
    g = lambda k: f['runout_over_lube_' + k]
    a = g('aspect_ratio')
    runout = (g('r_inf_m') - g('r0_m')) / g('r0_m')
    runout_edge = (g('edge_m') - g('r0_m')) / g('r0_m')
    rows.append((n, a, g('h0_m'), g('r0_m'), g('r_inf_m'), g('edge_m'), g('front_m'), runout,
                 runout_edge, g('lube'), g('r0_m') / D))
    print(f'n {n:5}  R0/d {g("r0_m") / D:4.1f}  a {a:5.2f}  (R_inf - R0)/R0 {runout:5.2f}  '
          f'edge {runout_edge:5.2f}  Lube {g("lube"):5.2f}')


for n in COUNTS:
    h = PER_SPHERE * n
    # The fill falls from h, then settles for 0.2 s; the collapse is over within 0.5 s.
    release = round(0.2 + math.sqrt(2 * h / 9.81), 2)
    text = re.sub(r'(?m)^count = .*$', f'count = {n}', base)
    text = re.sub(r'height = [0-9.e-]+ \}', f'height = {h:.4f} }}', text)
    text = re.sub(r'(?m)^hi = \[(.*), [0-9.e-]+\]$', lambda m: f'hi = [{m.group(1)}, {h + 0.01:.4f}]', text)
    text = re.sub(r'(?m)^lo = \[-0.09, -0.09,', 'lo = [-0.12, -0.12,', text)
    text = re.sub(r'(?m)^hi = \[0.09, 0.09,', 'hi = [0.12, 0.12,', text)
    text = re.sub(r'(?m)^release = .*$', f'release = {release}', text)
    text = re.sub(r'(?m)^duration = .*$', f'duration = {release + 0.5:.2f}', text)
    record(n, run(grains, text, work, f'collapse_n{n}'))
full = open(os.path.join(here, '..', 'examples', 'dem3d', 'collapse.toml')).read()
record(int(re.search(r'(?m)^count = (\d+)', full).group(1)), run(grains, full, work, 'collapse'))


def widened(f):
    """collapse.toml with the tube, fill and domain f times wider and taller (the same
    grains): the count grows as f³, the fall and spread times as √f."""
    n = int(round(3850 * f ** 3))
    t = re.sub(r'(?m)^count = .*$', f'count = {n}', full)
    t = t.replace('lo = [-0.18, -0.18, 0.0]', f'lo = [{-0.18 * f:.3f}, {-0.18 * f:.3f}, 0.0]')
    t = t.replace('hi = [0.18, 0.18, 0.17]', f'hi = [{0.18 * f:.3f}, {0.18 * f:.3f}, {0.17 * f:.3f}]')
    t = t.replace('radius = 0.03\ninside', f'radius = {0.03 * f:.4f}\ninside')
    t = t.replace('radius = 0.03, height = 0.16', f'radius = {0.03 * f:.4f}, height = {0.16 * f:.4f}')
    release = round(0.4 * f ** 0.5 + 0.05, 2)
    t = re.sub(r'(?m)^release = .*$', f'release = {release}', t)
    t = re.sub(r'(?m)^duration = .*$', f'duration = {release + 0.5 * f ** 0.5 + 0.1:.2f}', t)
    return n, t


for f in ([1.5, 2.0] if wide else []):
    n, text = widened(f)
    record(n, run(grains, text, work, f'collapse_x{f}'))
with open(out, 'w') as f:
    f.write('count,aspect_ratio,h0_m,r0_m,r_inf_m,edge_m,front_m,runout,runout_edge,lube,'
            'r0_over_d\n')
    for r in rows:
        f.write('{},{:.4f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.4f},{:.4f},{:.4f},{:.2f}\n'
                .format(*r))
print(out)
