#!/usr/bin/env python3
"""A copy of a ring example with another duration, frames and history rows, for the
studies of VALIDATION.md ("Band fraction of test 1", "Jetting mode past 100 µs"): the
example's own [[check]], [analysis] and [analysis.dispersal] tables are dropped, packing
paths made absolute, and EXTRA (a TOML file: [contact], [analysis], ...) appended.

usage: python3 bench/ring_variant.py EXAMPLE.toml OUT.toml NAME DURATION FRAMES HISTORY [EXTRA.toml]
No dependencies beyond the standard library.
"""
import os
import re
import sys

src, dst, name, dur, frames, hist = sys.argv[1:7]
extra = open(sys.argv[7]).read() if len(sys.argv) > 7 else ""
base = os.path.dirname(os.path.abspath(src))
out, skip, table = [], False, False
for line in open(src):
    s = line.strip()
    if s.startswith('['):
        table = True
        skip = s in ('[[check]]', '[analysis.dispersal]', '[analysis]')
    if skip:
        continue
    key = s.split(' = ', 1)[0]
    if key == 'name' and not table:
        line = f'name = "{name}"\n'
    elif key == 'duration':
        line = f'duration = {dur}\n'
    elif key == 'frames':
        line = f'frames = {frames}\n'
    elif key == 'history':
        line = f'history = {hist}\n'
    elif key == 'snapshots':
        line = 'snapshots = []\n'
    elif re.match(r'(spec|path) = "', s):
        k, v = s.split(' = ', 1)
        line = f'{k} = "{os.path.join(base, v.strip(chr(34)))}"\n'
    out.append(line)
open(dst, "w").write("".join(out) + "\n" + extra)
