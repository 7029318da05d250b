"""One run of a sweep over a 3D example (bench/drum_sweep.py, bench/silo_sweep.py): the
scenario TEXT written to WORK/NAME.toml, run by GRAINS into WORK/NAME, its summary.json
returned. Exit 2 (a check outside its band) still leaves the figures to read."""
import json
import os
import subprocess
import sys


def run(grains, text, work, name):
    toml = os.path.join(work, name + '.toml')
    open(toml, 'w').write(text)
    out = os.path.join(work, name)
    code = subprocess.run([grains, 'run', toml, '--out', out],
                          stdout=subprocess.DEVNULL).returncode
    if code not in (0, 2):
        sys.exit(f'{name}: grains exited {code}')
    return json.load(open(os.path.join(out, 'summary.json')))
