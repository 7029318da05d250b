#!/usr/bin/env bash
# Regenerate decks, run LAMMPS on each, check physics, check the Python transcription of SPEC.md
# against LAMMPS bit for bit, and rewrite tables/. Needs `lmp` (Debian: apt-get install -y lammps) and python3.
set -euo pipefail
cd "$(dirname "$0")"
lmp -h | grep -m1 "Large-scale" || true
python3 tools/make_decks.py
cd decks && mkdir -p out logs
for f in *.in; do n=${f%.in}; lmp -in "$f" -log "logs/$n.log" -screen none; done
cd ..
python3 tools/analyze.py
python3 tools/ref_granular.py
python3 tools/make_tables.py
du -sh tables
