#!/usr/bin/env bash
# Regenerate decks, run LAMMPS on each, check the Python transcription (tools/ref_hooke.py) against
# LAMMPS bit for bit, check the physics, and rewrite tables/. Needs `lmp` (Debian: apt-get install -y lammps), python3.
set -euo pipefail
cd "$(dirname "$0")"
lmp -h | grep -m1 "Large-scale" || true
python3 tools/make_decks.py
cd decks && mkdir -p out logs
for f in *.in; do n=${f%.in}; lmp -in "$f" -log "logs/$n.log" -screen none; done
cd ..
python3 tools/ref_hooke.py | tee decks/logs/ref_hooke.txt
python3 tools/analyze.py | tee decks/logs/analyze.txt
python3 tools/make_tables.py
du -sh tables
