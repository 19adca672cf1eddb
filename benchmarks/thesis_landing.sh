#!/usr/bin/env bash
# The thesis bunny run to the end: the implementation of Snow thesis 2015's own 91,897-particle bunny (its point
# cloud, as in `firn bench --thesis-cloud`: scaled by 15.74, 6.25e-3 kg per particle, E = 6e6 Pa, 201³ cells of
# 0.05 m, cubic B-splines, PIC/FLIP 0.95) falls 0.44 m to the floor, lands and settles, for FRAMES frames at 30 Hz
# (default 12: 0.4 s), once explicitly at 2.5e-4 s (near its elastic bound h / c, 2.4e-4 s with the snow's
# hardening at its critical compression) and once semi-implicitly at the thesis's own step of 1e-3 s. `firn bench`'s thesis table times a few steps of the fall, where the solve
# is cheapest; this run includes the landing, where it is dearest. Prints each run's cost per simulated second
# (the frames' wall_ms in stats.csv, frame 0's start-up left out), its solver iterations and residuals, and the
# ratio of the two costs; a run that did not finish is said so, and no ratio is given.
#   bash benchmarks/thesis_landing.sh CLOUD [OUT]     (FIRN=path/to/firn, FRAMES=N)
set -euo pipefail

if [ $# -lt 1 ] || [ ! -f "$1" ]; then
  echo "usage: $0 CLOUD [OUT] (CLOUD: the thesis implementation's bunny, one x,y,z per line)" >&2
  exit 2
fi
cloud=$(realpath "$1")
out=${2:-thesis-landing}
firn=${FIRN:-build/release/firn}
frames=${FRAMES:-12}
mkdir -p "$out"

# The density the cloud's particles stand for: 6.25e-3 kg over the cube of their spacing (0.002 × 15.74 m), as
# firn bench derives it; the elastic wave speed, and so the explicit bound, follows from it.
for run in explicit:2.5e-4 semi_implicit:1e-3; do
  integrator=${run%%:*}
  dt=${run#*:}
  cat > "$out/$integrator.json" << EOF
{
  "name": "thesis bunny, $integrator",
  "grid": { "cells": [201, 201, 201], "cell_size": 0.05 },
  "time": { "dt": $dt, "frame_rate": 30, "frames": $frames },
  "solver": { "kernel": "cubic", "transfer": "pic_flip", "flip_ratio": 0.95, "atomics": "fixed",
              "integrator": "$integrator" },
  "materials": { "snow": { "model": "snow", "youngs_modulus": 6e6, "poisson_ratio": 0.2, "density": 200.4,
                           "critical_compression": 1e-2, "critical_stretch": 1e-3, "hardening": 30 } },
  "bodies": [ { "shape": "points", "path": "$cloud", "scale": 15.74, "translate": [5, 0, 5],
                "material": "snow", "particle_mass": 6.25e-3 } ]
}
EOF
  status=0
  "$firn" run "$out/$integrator.json" --no-ply --out "$out/$integrator" > "$out/$integrator.log" 2>&1 || status=$?
  echo "$status" > "$out/$integrator.exit"
done

# Σ wall_ms and steps over frames 1…N, the most iterations and the largest residual of any frame; the line on
# stdout, the cost per simulated second (ms) on stderr.
summarize() {
  awk -F, -v name="$1" -v frame_rate=30 '
    /^#/ { next }
    !header { for (c = 1; c <= NF; ++c) column[$c] = c; header = 1; next }
    $1 > 0 {
      wall += $column["wall_ms"]; steps += $column["steps"]; frames = $1
      if ($column["solver_iterations"] > iterations) iterations = $column["solver_iterations"]
      if ($column["solver_residual"] > residual) residual = $column["solver_residual"]
    }
    END {
      if (steps == 0) { printf "%s: no frame finished\n", name; exit 1 }
      seconds = frames / frame_rate
      printf "%s: %d frames (%.3f s), %d steps, %.1f ms per step, %.1f s per simulated second", name, frames,
             seconds, steps, wall / steps, wall / 1000 / seconds
      if (iterations > 0) printf ", at most %d iterations and residual %.3g in a step", iterations, residual
      printf "\n"
      print wall / seconds > "/dev/stderr"
    }' "$out/$1/stats.csv"
}
finished=0
for integrator in explicit semi_implicit; do
  rm -f "$out/$integrator.cost"
  status=$(cat "$out/$integrator.exit")
  if [ "$status" != 0 ]; then
    echo "$integrator: did not finish (firn run exit $status; $out/$integrator.log says why):"
    tail -3 "$out/$integrator.log"
  fi
  if [ -f "$out/$integrator/stats.csv" ] && summarize "$integrator" 2> "$out/$integrator.cost" && [ "$status" = 0 ]; then
    finished=$((finished + 1))
  fi
done
if [ "$finished" = 2 ]; then
  awk -v e="$(cat "$out/explicit.cost")" -v s="$(cat "$out/semi_implicit.cost")" \
    'BEGIN { printf "semi-implicit at 1e-3 s costs %.2fx the explicit run at 2.5e-4 s per simulated second\n", s / e }'
fi
