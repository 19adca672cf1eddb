#!/usr/bin/env bash
# Runs over several processes (docs/distributed.md), measured: strong scaling of the thesis bunny and weak scaling of
# a row of snowballs (one per rank), for 1 to 4 ranks of one renderer thread each (and one rank of two threads, the
# machine's other way to use two cores). Per configuration: ms per step, the speed-up over one rank, and from the
# run's own count the grid sums exchanged per step against what the grid passes move, the time exchanging and
# migrating, and the load imbalance. Writes strong.csv and weak.csv to the output folder; benchmarks/README.md reads
# them.
#   benchmarks/mpi_scaling.sh [FIRN] [OUT] [FRAMES]     (defaults: build/release/firn, firn-mpi-bench, 1)
set -euo pipefail
cd "$(dirname "$0")/.."
firn=$(realpath "${1:-build/release/firn}")
out=${2:-firn-mpi-bench}
frames=${3:-1}
mkdir -p "$out"
mpirun=(mpirun --oversubscribe --allow-run-as-root)

# One run: ranks, threads per rank, scene → a CSV row (after the configuration's own columns).
measure() {
  local ranks=$1 threads=$2 scene=$3 work
  work=$(mktemp -d)
  if [ "$ranks" -eq 1 ]; then
    LP_NUM_THREADS=$threads "$firn" run "$scene" --frames "$frames" --no-ply --out "$work/run" > "$work/log" 2>&1
  else
    "${mpirun[@]}" -np "$ranks" -x LP_NUM_THREADS="$threads" "$firn" run "$scene" --frames "$frames" --no-ply \
      --out "$work/run" > "$work/log" 2>&1
  fi
  # "wrote 2 frames (182841 particles, 334 steps) … : 181.18 ms per step" and, over several ranks, "per step 230.0 KiB
  # of grid sums exchanged (5.2% of the 4.41 MiB …), 1.30 ms exchanging …, 12 particles migrated; load imbalance 1.030"
  local particles steps ms halo share exchange imbalance
  particles=$(sed -n 's/.*wrote [0-9]* frames (\([0-9]*\) particles.*/\1/p' "$work/log")
  steps=$(sed -n 's/.*particles, \([0-9]*\) steps).*/\1/p' "$work/log")
  ms=$(sed -n 's/.*: \([0-9.]*\) ms per step.*/\1/p' "$work/log")
  halo=$(sed -n 's/.*per step \([0-9.]*\) KiB of grid sums.*/\1/p' "$work/log")
  share=$(sed -n 's/.*KiB of grid sums exchanged (\([0-9.]*\)% of.*/\1/p' "$work/log")
  exchange=$(sed -n 's/.*MiB the grid passes move), \([0-9.]*\) ms exchanging.*/\1/p' "$work/log")
  imbalance=$(sed -n 's/.*load imbalance \([0-9.]*\).*/\1/p' "$work/log")
  [ -n "$ms" ] || { cat "$work/log"; exit 1; }
  echo "$particles,$steps,$ms,${halo:-0},${share:-0},${exchange:-0},${imbalance:-1}"
  rm -rf "$work"
}

header="ranks,threads_per_rank,particles,steps,ms_per_step,speedup,halo_kib_per_step,halo_percent_of_grid_bytes,exchange_ms_per_step,imbalance"

# Measures one configuration and appends its row to CSV, with its speed-up over the table's first row (weak
# scaling's efficiency: one rank's time over N ranks' on N times the particles).
table_row() {
  local csv=$1 ranks=$2 threads=$3 scene=$4 row particles steps ms
  row=$(measure "$ranks" "$threads" "$scene")
  IFS=, read -r particles steps ms _ <<< "$row"
  [ -n "$base" ] || base=$ms
  echo "$ranks,$threads,$particles,$steps,$ms,$(awk "BEGIN { printf \"%.3f\", $base / $ms }"),${row#*,*,*,}" >> "$csv"
  echo "$(basename "$csv" .csv): $ranks rank(s) × $threads thread(s): $ms ms per step"
}

echo "$header" > "$out/strong.csv"
base=""
for config in "1 1" "1 2" "2 1" "3 1" "4 1"; do
  set -- $config
  table_row "$out/strong.csv" "$1" "$2" assets/scenes/bunny_thesis.json
done

# The weak row: N snowballs of 14k particles in a row along z, touching, falling onto a floor: the ranks' slabs cut
# the row between the balls, where their stencils meet.
snowballs() {
  local n=$1 file=$2 bodies="" z
  for ((i = 0; i < n; ++i)); do
    z=$(awk "BEGIN { print 0.24 + 0.3 * $i }")
    bodies+="${bodies:+, }{ \"shape\": \"sphere\", \"center\": [0.3, 0.4, $z], \"radius\": 0.15, \"material\": \"snow\", \"velocity\": [0, -2, 0], \"particles_per_cell\": 8 }"
  done
  cat > "$file" <<JSON
{ "name": "snowball-row-$n", "grid": { "origin": [0, 0, 0], "cells": [30, 40, $((15 * n + 9))], "cell_size": 0.02 },
  "time": { "dt": 2e-4, "frame_rate": 30, "frames": 1 },
  "solver": { "kernel": "quadratic", "transfer": "apic", "atomics": "fixed" },
  "materials": { "snow": { "preset": "stomakhin" } },
  "bodies": [ $bodies ],
  "colliders": [ { "type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0], "friction": 0.4, "boundary": "slip" } ] }
JSON
}
echo "$header" > "$out/weak.csv"
base=""
for ranks in 1 2 3 4; do
  snowballs "$ranks" "$out/snowball_row_$ranks.json"
  table_row "$out/weak.csv" "$ranks" 1 "$out/snowball_row_$ranks.json"
done
echo "wrote $out/strong.csv and $out/weak.csv"
