#!/usr/bin/env bash
# A run over several processes writes the same bytes as one process (docs/distributed.md): runs SCENE with
# `firn run` and with `mpirun -np NP firn run`, the same options, and compares every file it writes byte for byte
# (frames, pictures, meshes, VDB caches, checkpoints, bodies.csv), and stats.csv without its wall_ms column and its
# comment (the wall time and the transfers' timing, which chose a shape that changes no number, are all that may
# differ).
#   same_bytes.sh FIRN WORK NP SCENE [firn run options …]
set -euo pipefail
firn=$1 work=$2 np=$3 scene=$4
shift 4
rm -rf "$work"
mkdir -p "$work"
"$firn" run "$scene" --out "$work/one" "$@" > "$work/one.log" 2>&1 || { cat "$work/one.log"; exit 1; }
mpirun --oversubscribe --allow-run-as-root -np "$np" "$firn" run "$scene" --out "$work/many" "$@" \
  > "$work/many.log" 2>&1 || { cat "$work/many.log"; exit 1; }
grep "processes, slabs" "$work/many.log" || true

failed=0
frames=$(cd "$work/one" && ls | grep -vx stats.csv)
[ -n "$frames" ] || { echo "no frames written"; exit 1; }
for frame in $frames; do
  cmp "$work/one/$frame" "$work/many/$frame" || failed=1
done
[ "$(cd "$work/many" && ls | grep -vx stats.csv)" = "$frames" ] || { echo "the runs wrote different files"; failed=1; }
without_wall_time() { awk -F, '/^#/ { next }
  !header { header = 1; for (i = 1; i <= NF; i++) if ($i == "wall_ms") skip = i }
  { line = ""; for (i = 1; i <= NF; i++) if (i != skip) line = line (line == "" ? "" : ",") $i; print line }' "$1"; }
diff <(without_wall_time "$work/one/stats.csv") <(without_wall_time "$work/many/stats.csv") || failed=1
if [ "$failed" -ne 0 ]; then
  echo "FAILED: mpirun -np $np differs from one process on $scene $*"
  exit 1
fi
echo "the same bytes: $(echo "$frames" | wc -l) files and stats.csv of $scene $*, one process and $np"
