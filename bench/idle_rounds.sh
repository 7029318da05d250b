#!/bin/bash
# Interleaved rounds on an idle machine: the 2D 100 k bed on 1 and 2 ranks beside
# LAMMPS on 1 and 2 ranks (issue 25), and the 3D 50 k bed on 1 and 2 threads beside
# LAMMPS (issue 24); each grains configuration also with a reference build OLD.
#
#   bench/idle_rounds.sh GRAINS OLD_GRAINS OUT [ROUNDS]
#
# GRAINS and OLD_GRAINS: release builds with `--features mpi`. BED2D: a directory with
# bed_20000.data (`../shared/peers/dem/in.settle.lmp`) and in.bench100k.lmp (the peers'
# in.bench.lmp with `replicate 5 1 1` after `read_data`); BED3D: bed3d.data
# (`../shared/peers/dem3d/in.settle3d.lmp`). Run from the repository's root.
set -u
NEW=$1; OLD=$2; OUT=$3; R=${4:-4}
BED2D=${BED2D:-/work/bed2d}; BED3D=${BED3D:-/work/bed3d}; ROOT=$PWD
M="mpirun --allow-run-as-root --bind-to core"
rate() { grep -o 'particle-steps/s: [0-9.e+]*' | tail -1 | awk '{print $2}'; }
hash() { grep -o 'state-hash: [0-9a-f]*' | tail -1 | awk '{print $2}'; }
loop2() { awk '/^Loop time/ && / 2000 steps/{print 100000*2000/$4}' | tail -1; }
loop3() { awk '/^Loop time/ && / 500 steps/{print 50184*500/$4}' | tail -1; }
bed="--lammps-data bed_20000.data --tile 5 --steps 2000 --threads 1"
{ lscpu | grep "Model name"; uptime; date -u; } >"$OUT"
for r in $(seq "$R"); do
    cd "$BED2D"
    a=$($NEW bench dem $bed 2>&1 | tee /tmp/idle_a.log | rate)
    o=$($OLD bench dem $bed 2>&1 | rate)
    c=$($M -np 2 $NEW bench dem $bed 2>&1 | tee /tmp/idle_c.log | rate)
    d=$(lmp -in in.bench100k.lmp -var data bed_20000.data -log none 2>&1 | loop2)
    e=$($M -np 2 lmp -in in.bench100k.lmp -var data bed_20000.data -log none 2>&1 | loop2)
    echo "2d round $r new1r $a old1r $o new2r $c lammps1 $d lammps2 $e" \
        "hash1 $(hash </tmp/idle_a.log) hash2 $(hash </tmp/idle_c.log)" >>"$OUT"
    cd "$ROOT"
    b3="--dim 3 --lammps-data $BED3D/bed3d.data --steps 500"
    f=$($NEW bench dem $b3 --threads 1 2>&1 | rate)
    g=$($OLD bench dem $b3 --threads 1 2>&1 | rate)
    h=$($NEW bench dem $b3 --threads 2 2>&1 | rate)
    l=$(lmp -in bench/in.check3d.lmp -var data "$BED3D/bed3d.data" -var nrun 500 -log none 2>&1 | loop3)
    echo "3d round $r new1t $f old1t $g new2t $h lammps $l" >>"$OUT"
done
uptime >>"$OUT"
