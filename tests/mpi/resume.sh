#!/usr/bin/env bash
# A checkpoint resumes with any number of processes (docs/distributed.md): SCENE runs in one process and in
# FROM_NP, checkpointing every 2 frames; the FROM_NP run's checkpoint of frame 2 is resumed with mpirun -np TO_NP,
# and its checkpoint of frame 4 in one process. Every frame either resumed run writes is the first run's, byte for
# byte.
#   resume.sh FIRN WORK SCENE FROM_NP TO_NP
set -euo pipefail
firn=$1 work=$2 scene=$3 from=$4 to=$5
mpirun=(mpirun --oversubscribe --allow-run-as-root)
rm -rf "$work"
mkdir -p "$work"
run() { local log=$1; shift; "$@" > "$work/$log.log" 2>&1 || { cat "$work/$log.log"; exit 1; }; }
run one "$firn" run "$scene" --checkpoint-every 2 --out "$work/one"
run from "${mpirun[@]}" -np "$from" "$firn" run "$scene" --checkpoint-every 2 --out "$work/from"
run to "${mpirun[@]}" -np "$to" "$firn" run "$scene" --resume "$work/from/checkpoint_0002.firn" --out "$work/to"
run back "$firn" run "$scene" --resume "$work/from/checkpoint_0004.firn" --out "$work/back"

failed=0
for resumed in to back; do
  frames=$(cd "$work/$resumed" && ls frame_*.ply)
  [ -n "$frames" ] || { echo "$resumed: no frames written"; exit 1; }
  for frame in $frames; do cmp "$work/one/$frame" "$work/$resumed/$frame" || failed=1; done
done
for checkpoint in $(cd "$work/one" && ls checkpoint_*.firn); do
  cmp "$work/one/$checkpoint" "$work/from/$checkpoint" || failed=1
done
if [ "$failed" -ne 0 ]; then
  echo "FAILED: resuming $scene across process counts ($from → $to, $from → 1) changed the frames"
  exit 1
fi
echo "the same bytes: checkpoints of one process and $from; resumed with $to and with one, the frames of one"
