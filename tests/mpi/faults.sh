#!/usr/bin/env bash
# A failing rank ends a run over several processes at once (docs/distributed.md), with its message:
#   - bad input (a semi-implicit scene, which runs in one process only): exit 2, said once, naming the key;
#   - a scene that goes unstable: exit 3 within 30 s, a rank's message naming itself and the step;
#   - rank 1 killed (SIGKILL) mid-run: mpirun ends within 30 s, non-zero, naming rank 1 and the signal, rank 0 saying
#     at which step; the frames written before are whole (each the size of frame 0: the scene keeps its particles).
#   faults.sh FIRN WORK UNSTABLE_SCENE LONG_SCENE
set -euo pipefail
firn=$1 work=$2 unstable=$3 long=$4
mpirun=(mpirun --oversubscribe --allow-run-as-root)
rm -rf "$work"
mkdir -p "$work"
failed=0

sed 's/"atomics": "fixed"/"atomics": "fixed", "integrator": "semi_implicit"/' "$unstable" > "$work/semi_implicit.json"
status=0
"${mpirun[@]}" -np 2 "$firn" run "$work/semi_implicit.json" --out "$work/refused" > "$work/refused.log" 2>&1 || status=$?
if [ "$status" -ne 2 ] || [ "$(grep -c "solver.integrator: the semi-implicit solve runs in one process only" "$work/refused.log")" -ne 1 ]; then
  cat "$work/refused.log"
  echo "FAILED: the semi-implicit scene ended with status $status, not refused once with exit 2"
  failed=1
fi

start=$(date +%s)
status=0
"${mpirun[@]}" -np 2 "$firn" run "$unstable" --out "$work/unstable" > "$work/unstable.log" 2>&1 || status=$?
seconds=$(( $(date +%s) - start ))
if [ "$status" -ne 3 ] || [ "$seconds" -gt 30 ] || ! grep -q "error (rank [01] of 2): the simulation became unstable" "$work/unstable.log" ||
   ! grep -q "step [0-9]* (t" "$work/unstable.log"; then
  cat "$work/unstable.log"
  echo "FAILED: the unstable run ended with status $status after $seconds s"
  failed=1
fi

status=0
"${mpirun[@]}" -np 2 "$firn" run "$long" --frames 1000 --out "$work/killed" > "$work/killed.log" 2>&1 &
launcher=$!
for _ in $(seq 600); do [ -f "$work/killed/frame_0002.ply" ] && break; sleep 0.1; done
killed=""
for pid in $(pgrep -f -- "--out $work/killed" || true); do
  if tr '\0' '\n' < "/proc/$pid/environ" 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=1"; then
    kill -9 "$pid"
    killed=$pid
  fi
done
start=$(date +%s)
wait "$launcher" || status=$?
seconds=$(( $(date +%s) - start ))
size=$(stat -c %s "$work/killed/frame_0000.ply")
for frame in "$work"/killed/frame_*.ply; do
  [ "$(stat -c %s "$frame")" = "$size" ] || { echo "FAILED: $frame is not whole"; failed=1; }
done
if [ -z "$killed" ] || [ "$status" -eq 0 ] || [ "$seconds" -gt 30 ] ||
   ! grep -q "process rank 1 .* exited on signal 9" "$work/killed.log" ||
   ! grep -q "rank 0 of 2: stopped by mpirun at step [0-9]*, after another rank of the run ended" "$work/killed.log"; then
  cat "$work/killed.log"
  echo "FAILED: killing rank 1 (pid ${killed:-none found}) ended the run with status $status after $seconds s"
  failed=1
fi
[ "$failed" -eq 0 ] && echo "failing ranks end the run: unstable (status 3), killed (status $status, $seconds s)"
exit "$failed"
