#!/usr/bin/env bash
# A run over several processes writes the same bytes as one process (docs/distributed.md): runs SCENE with
# `firn run` and with `mpirun -np NP firn run`, the same options, and compares every file it writes byte for byte
# (frames, pictures, meshes, VDB caches, checkpoints, bodies.csv), stats.csv without its wall_ms column (the wall time
# is all that may differ there), and of run.json what the run did (the scene and its fingerprint, the frames, steps and
# particles, how it ended) but not how it ran (its command line, processes, timings).
#   same_bytes.sh FIRN WORK NP SCENE [firn run options …]
set -euo pipefail
firn=$1 work=$2 np=$3 scene=$4
shift 4
rm -rf "$work"
mkdir -p "$work"
"$firn" run "$scene" --out "$work/one" "$@" > "$work/one.log" 2>&1 || { cat "$work/one.log"; exit 1; }
mpirun --oversubscribe --allow-run-as-root -np "$np" "$firn" run "$scene" --out "$work/many" "$@" \
  > "$work/many.log" 2>&1 || { cat "$work/many.log"; exit 1; }
# Under mpirun the ranks share the domain and say so: copies of one process each would write the same files too.
grep "processes, slabs" "$work/many.log" || { echo "FAILED: mpirun -np $np ran no shared domain"; cat "$work/many.log"; exit 1; }

failed=0
frames=$(cd "$work/one" && ls | grep -vx -e stats.csv -e run.json)
[ -n "$frames" ] || { echo "no frames written"; exit 1; }
for frame in $frames; do
  cmp "$work/one/$frame" "$work/many/$frame" || failed=1
done
[ "$(cd "$work/many" && ls | grep -vx -e stats.csv -e run.json)" = "$frames" ] || { echo "the runs wrote different files"; failed=1; }
without_wall_time() { awk -F, '!header { header = 1; for (i = 1; i <= NF; i++) if ($i == "wall_ms") skip = i }
  { line = ""; for (i = 1; i <= NF; i++) if (i != skip) line = line (line == "" ? "" : ",") $i; print line }' "$1"; }
diff <(without_wall_time "$work/one/stats.csv") <(without_wall_time "$work/many/stats.csv") || failed=1
what_ran() { python3 -c 'import json, sys
run = json.load(open(sys.argv[1]))
print(json.dumps({key: run[key] for key in ("firn_version", "scene", "frames", "steps", "particles", "exit")}, indent=1))' "$1"; }
diff <(what_ran "$work/one/run.json") <(what_ran "$work/many/run.json") || failed=1
if [ "$failed" -ne 0 ]; then
  echo "FAILED: mpirun -np $np differs from one process on $scene $*"
  exit 1
fi
echo "the same bytes: $(echo "$frames" | wc -l) files and stats.csv of $scene $*, one process and $np"
