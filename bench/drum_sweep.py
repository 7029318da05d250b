#!/usr/bin/env python3
"""The rotating drum's dynamic angle of repose against sliding friction mu and rolling
friction mu_r (VALIDATION.md, "Rotating drum"): runs examples/dem3d/drum_small.toml (or
with --full examples/dem3d/drum.toml, the drum twice as wide in grains) with each
(mu, mu_r) of the sweep, reads the measured angle and torque ratio from each run's
summary.json and writes them to OUT.csv (columns mu, mu_r, angle_deg, torque_ratio).
Then `cargo run -p grains-sim --example drum_repose -- OUT.csv [MORE.csv ...]` draws
OUT.png.

usage: python3 bench/drum_sweep.py GRAINS_BINARY OUT.csv [WORK_DIR] [--full]
No dependencies beyond the standard library; each run takes about 10 s on 2 cores
(--full: about 4 min).
"""
import os
import re
import sys
import tempfile

from sweep_run import run

# mu at the example's mu_r, then mu_r at the example's mu.
SWEEP = [(0.1, 0.05), (0.3, 0.05), (0.5, 0.05), (0.8, 0.05),
         (0.5, 0.0), (0.5, 0.1), (0.5, 0.2)]

args = [a for a in sys.argv[1:] if a != '--full']
full = '--full' in sys.argv[1:]
grains, out = args[0:2]
work = args[2] if len(args) > 2 else tempfile.mkdtemp()
here = os.path.dirname(os.path.abspath(__file__))
example = 'drum.toml' if full else 'drum_small.toml'
base = open(os.path.join(here, '..', 'examples', 'dem3d', example)).read()
rows = []
for mu, mu_r in SWEEP:
    text = re.sub(r'(?m)^friction = .*$', f'friction = {mu}', base)
    text = re.sub(r'(?m)^mu_r = .*$', f'mu_r = {mu_r}', text)
    name = f'drum{"_full" if full else ""}_mu{mu}_mur{mu_r}'
    checks = {c['name']: c['measured'] for c in run(grains, text, work, name)['checks']}
    rows.append((mu, mu_r, checks['dynamic_angle_of_repose'], checks['drum_torque_over_weight_moment']))
    print(f'mu {mu:4}  mu_r {mu_r:4}  angle {rows[-1][2]:6.2f} deg  torque/moment {rows[-1][3]:.4f}')
with open(out, 'w') as f:
    f.write('mu,mu_r,angle_deg,torque_ratio\n')
    for r in rows:
        f.write('{},{},{:.3f},{:.5f}\n'.format(*r))
print(out)
