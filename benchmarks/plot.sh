#!/usr/bin/env bash
# Plots the tables `firn bench` writes: DIR/particles.csv → DIR/particles.png, and so on for grid, passes,
# tradeoff, p2g_atomics and surface (each table that is there). `firn bench` runs this at its end; by hand:
#   bash benchmarks/plot.sh DIR
# Needs gnuplot (Debian: apt-get install gnuplot-nox). Only rows whose status is "ok" are plotted.
set -euo pipefail

if [ $# -ne 1 ] || [ ! -d "$1" ]; then
  echo "usage: $0 DIR (a folder of firn bench tables)" >&2
  exit 2
fi
dir=$1
if ! command -v gnuplot > /dev/null; then
  echo "plot.sh: gnuplot is not installed (Debian: apt-get install gnuplot-nox)" >&2
  exit 1
fi

# The renderer the tables were measured on, for the titles (machine.txt's first line).
renderer=""
if [ -f "$dir/machine.txt" ]; then
  renderer=$(sed -n 's/^renderer: //p' "$dir/machine.txt" | head -n 1)
fi

# Common settings: CSV with a header row (columns are read by name), PNG through cairo.
preamble() {
  cat <<EOF
set datafile separator ","
set datafile columnheaders
set terminal pngcairo size 960,640 noenhanced font ",11"
set grid
set key top left
ok = 'strcol("status") eq "ok"'
EOF
}

plot_table() {
  local name=$1 script=$2
  if [ ! -f "$dir/$name.csv" ]; then return; fi
  { preamble; printf 'set output "%s"\nfile = "%s"\nrenderer = "%s"\n' "$dir/$name.png" "$dir/$name.csv" \
      "${renderer//\"/}"; echo "$script"; } | gnuplot
  echo "plot.sh: wrote $dir/$name.png" >&2
}

plot_table particles '
set title "Time per step against particles (the bunny on the thesis grid)\n".renderer
set logscale xy
set key top left
set xlabel "particles"
set ylabel "ms per step (median)"
family(shape) = (shape eq "tiles") ? "tiles" : "blocks"
series(name, kernel, of) = (strcol("series") eq name && strcol("kernel") eq kernel && \
                            strcol("atomics")."_".family(strcol("transfer_shape")) eq of && @ok) ? column("particles") : NaN
stats file using (@ok ? log(column("particles")) : NaN) name "logParticles" nooutput
stats file using (@ok ? log(column("ms_per_step")) : NaN) name "logMs" nooutput
guide(x) = exp(logMs_mean) * x / exp(logParticles_mean)
sumsList = "fixed_tiles fixed_blocks float_tiles"
colours = "#1f77b4 #2ca02c #d62728"
plot for [i=1:3] file using (series("unscaled", "cubic", word(sumsList, i))):"ms_per_step" with linespoints \
       lc rgb word(colours, i) pt 7 title word(sumsList, i)." cubic, unscaled (one bunny, 4, 8, 16 … per cell)", \
     for [i=1:3] file using (series("scaled", "cubic", word(sumsList, i))):"ms_per_step" with linespoints \
       lc rgb word(colours, i) pt 5 dashtype 3 title word(sumsList, i)." cubic, scaled (8 per cell, larger bunny)", \
     for [i=1:2] file using (series("scaled", "quadratic", word(sumsList, i))):"ms_per_step" with linespoints \
       lc rgb word(colours, i) pt 9 dashtype 2 title word(sumsList, i)." quadratic, scaled", \
     guide(x) with lines dashtype 2 lc rgb "gray40" title "slope 1 (linear)"
'

plot_table grid '
set title "Time per step against grid size, the same particles\n".renderer
set logscale x
set yrange [0:*]
set xlabel "grid nodes"
set ylabel "ms per step (median)"
set key bottom right
series(atomics) = (strcol("atomics") eq atomics && @ok) ? column("grid_cells") : NaN
plot for [i=1:2] file using (series(word("fixed float", i))):"ms_per_step" with linespoints pt 7 \
       title word("fixed float", i)." atomics"
'

plot_table domain '
set title "Time per step against the domain, one snowball of 50,000 particles\n".renderer
set logscale x
set yrange [0:*]
set y2range [0:*]
set xlabel "domain nodes"
set ylabel "ms per step (median)"
set y2label "grid memory (MiB)"
set y2tics
set key bottom right
plot file using (@ok ? column("grid_cells") : NaN):"ms_per_step" with linespoints pt 7 title "ms per step", \
     file using (@ok ? column("grid_cells") : NaN):(column("pool_mib") + column("block_map_mib")) axes x1y2 \
       with linespoints pt 5 title "grid memory: block pool and map"
'

# passes: a panel per series (atomics, shape, integrator, kernel and particles), each pass a pair of bars; one chart of
# every series' passes side by side had too many bars to read their names.
plot_passes() {
  if [ ! -f "$dir/passes.csv" ]; then return; fi
  local tmp panels
  tmp=$(mktemp -d)
  awk -F, -v out="$tmp" '
    function field(name) { return (name in column) ? $column[name] : "" }  # tables of older builds lack some
    NR == 1 { header = $0; for (i = 1; i <= NF; ++i) column[$i] = i; next }
    {
      series = field("atomics") " " field("transfer_shape") " " field("integrator") " " field("kernel") ", " \
               field("particles") " particles"
      if (!(series in table)) {
        table[series] = out "/" (++panels) ".csv"
        print header > table[series]
        print series > (out "/" panels ".title")
      }
      print >> table[series]
    }' "$dir/passes.csv"
  panels=$(find "$tmp" -name '*.csv' | wc -l)
  {
    preamble
    printf 'set terminal pngcairo size 960,%d noenhanced font ",10"\n' $((60 + 230 * panels))
    printf 'set output "%s"\n' "$dir/passes.png"
    printf 'set multiplot layout %d,1 title "Time per pass, each timed alone\\n%s"\n' "$panels" "${renderer//\"/}"
    echo 'set style data histograms'
    echo 'set style histogram clustered gap 1'
    echo 'set style fill solid 0.8 border -1'
    echo 'set yrange [0:*]'
    echo 'set ylabel "ms per step"'
    echo 'set key top left'
    echo 'set xtics rotate by -20 font ",8"'
    for ((i = 1; i <= panels; ++i)); do
      printf 'set title "%s"\n' "$(cat "$tmp/$i.title")"
      printf 'plot "%s" using "wall_ms":xtic(strcol("pass")) title "wall (dispatch to glFinish)", "" using "gpu_ms" title "GL_TIME_ELAPSED"\n' \
        "$tmp/$i.csv"
      echo 'unset key'
    done
    echo 'unset multiplot'
  } | gnuplot
  rm -rf "$tmp"
  echo "plot.sh: wrote $dir/passes.png" >&2
}
plot_passes

plot_table tradeoff '
set title "Elastic bar: period error against cost (Pareto front highlighted)\n".renderer
set logscale xy
set xlabel "ms of computing per simulated second"
set ylabel "relative period error against T/sqrt(kappa)"
set key top right
measured(front) = (@ok && column("error") > 0 && column("pareto") == front) ? column("ms_per_simulated_second") : NaN
plot file using (measured(0)):"error" with points pt 6 ps 1.5 lc rgb "gray50" title "configuration", \
     file using (measured(1)):"error" with points pt 7 ps 2 lc rgb "red" title "Pareto front", \
     file using (@ok && column("error") > 0 ? column("ms_per_simulated_second") : NaN):"error":"configuration" \
       with labels offset char 1,0.6 left font ",9" notitle
'

plot_table p2g_atomics '
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set multiplot layout 1,2 title "P2G with fixed-point and float atomics (reference bunny)\n".renderer
set yrange [0:*]
set ylabel "P2G ms per step (wall)"
set key top right
plot file using "p2g_ms":xtic(1) title "P2G time"
set logscale y
set yrange [*:*]
set format y "%.0e"
set ylabel "relative error against a double-precision sum"
set key top right font ",9"
plot file using "mass_max_rel_error":xtic(1) title "mass, max", \
     file using "mass_rms_rel_error" title "mass, RMS", \
     file using "momentum_max_rel_error" title "momentum, max", \
     file using "momentum_rms_rel_error" title "momentum, RMS"
unset multiplot
'

plot_table surface '
set multiplot layout 1,2 title "The snow surface per frame (field and mesh), beside a step (the thesis bunny, 8 per cell)\n".renderer
set logscale xy
set xlabel "particles (resolution 2)"
set ylabel "ms (median)"
set key top left font ",9"
particles(name) = (strcol("series") eq "particles" && @ok) ? column("particles") : NaN
plot file using (particles("")):"surface_ms" with linespoints pt 7 title "surface: field and mesh", \
     file using (particles("")):"splat_ms" with linespoints pt 5 dashtype 3 title "  of which the field (splat)", \
     file using (particles("")):"mesh_ms" with linespoints pt 9 dashtype 3 title "  of which the mesh", \
     file using (particles("")):"ms_per_step" with linespoints pt 6 lc rgb "gray40" title "one simulation step"
unset logscale x
set xlabel "surface.resolution (nodes per simulation cell, per axis)"
resolution(name) = (strcol("series") eq "resolution" && @ok) ? column("resolution") : NaN
plot file using (resolution("")):"surface_ms" with linespoints pt 7 title "surface: field and mesh", \
     file using (resolution("")):"splat_ms" with linespoints pt 5 dashtype 3 title "  of which the field (splat)", \
     file using (resolution("")):"mesh_ms" with linespoints pt 9 dashtype 3 title "  of which the mesh", \
     file using (resolution("")):"ms_per_step" with linespoints pt 6 lc rgb "gray40" title "one simulation step"
unset multiplot
'
