#include "io/EnergyPlot.h"

#include "Error.h"
#include "io/AtomicFile.h"
#include "io/ExternalProgram.h"

namespace firn {

namespace {

// gnuplot's string literal of `text`: in double quotes, with its backslashes and quotes escaped.
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '\\' || c == '"') out += '\\';
    out += c;
  }
  return out + "\"";
}

// The layers from the bottom: each stacked on those below (their running sums), filled between them. The energy held
// first, then the step's term, then what left: to the walls, and dissipated (below zero where energy was made from
// nothing).
constexpr const char* kProgram = R"gnuplot(set datafile separator ","
set datafile columnheaders
set terminal pngcairo size 1000,760 noenhanced font ",11"
set grid
set key below maxrows 4 width -2
set autoscale xfix
set xlabel "time (s)"
set ylabel "energy (J)"
# Each layer's top: the sum of the columns up to it (a function of a dummy, so that the using specs can call it).
l1(x) = column("potential_energy_j")
l2(x) = l1(x) + column("kinetic_energy_j")
l3(x) = l2(x) + column("elastic_energy_j")
l4(x) = l3(x) + column("bodies_potential_energy_j")
l5(x) = l4(x) + column("bodies_kinetic_energy_j")
l6(x) = l5(x) + column("step_energy_j")
l7(x) = l6(x) + column("walls_removed_j")
l8(x) = l7(x) + column("dissipated_energy_j")
plot file using "time_s":(0):(l1(0)) with filledcurves fc rgb "#9ecae1" title "potential (particles)", \
     file using "time_s":(l1(0)):(l2(0)) with filledcurves fc rgb "#3182bd" title "kinetic (particles)", \
     file using "time_s":(l2(0)):(l3(0)) with filledcurves fc rgb "#31a354" title "elastic (particles)", \
     file using "time_s":(l3(0)):(l4(0)) with filledcurves fc rgb "#fdd0a2" title "potential (rigid bodies)", \
     file using "time_s":(l4(0)):(l5(0)) with filledcurves fc rgb "#e6550d" title "kinetic (rigid bodies)", \
     file using "time_s":(l5(0)):(l6(0)) with filledcurves fc rgb "#fee391" title "the explicit step's term (symplectic Euler)", \
     file using "time_s":(l6(0)):(l7(0)) with filledcurves fc rgb "#bdbdbd" title "removed by the domain walls", \
     file using "time_s":(l7(0)):(l8(0)) with filledcurves fc rgb "#756bb1" title "dissipated (plasticity, friction, transfers)", \
     file using "time_s":(l8(0)) with lines lw 2 lc rgb "black" title "at the start, and entered since (work, arrivals, hardening, the bodies' coupling)"
)gnuplot";

}  // namespace

bool canPlot() { return findProgram("gnuplot").has_value(); }

void plotEnergy(const std::filesystem::path& statsCsv, const std::filesystem::path& folder, const std::string& title) {
  const std::filesystem::path png = folder / "energy.png";
  const std::filesystem::path program = folder / "energy.gp";
  const std::optional<std::filesystem::path> gnuplot = findProgram("gnuplot");
  if (!gnuplot) {
    throw InputError(png.string() + ": --plot needs the gnuplot program, which is not on the PATH (Debian: apt-get "
                     "install gnuplot-nox); the numbers are in " + statsCsv.string());
  }
  writeFileAtomically(program,
                      "# The energy budget of " + statsCsv.string() + ", as `firn run --plot` drew it: gnuplot " +
                          program.filename().string() + "\nfile = " + quoted(statsCsv.string()) + "\nset output " +
                          quoted(png.string()) + "\nset title " + quoted(title) + "\n" + kProgram,
                      "gnuplot program");
  const std::string failure = runProgram({gnuplot->string(), program.string()});
  if (!failure.empty()) throw InputError(png.string() + ": " + failure + " (its message, if any, is above)");
}

}  // namespace firn
