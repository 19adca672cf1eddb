#pragma once
// energy.png: a run's energy budget over time (stats.csv's energy columns, sim/EnergyAudit.h) as stacked areas, drawn
// by gnuplot when it is installed (Firn links no plotting library): what the particles and rigid bodies hold, the
// explicit step's term, what the domain walls removed and what was dissipated, stacked up to the energy at the start
// and all that entered since. A layer below zero is energy made from nothing (or, the step's term, the energy shown
// above the modified energy the step keeps). The gnuplot program is written beside it (energy.gp), to restyle.
#include <filesystem>
#include <string>

namespace firn {

// Whether gnuplot is on the PATH.
bool canPlot();

// Plots `statsCsv` (stats.csv's columns) into `folder`/energy.png, titled `title`, writing the program as
// `folder`/energy.gp. Throws InputError naming the file if gnuplot is missing or fails.
void plotEnergy(const std::filesystem::path& statsCsv, const std::filesystem::path& folder, const std::string& title);

}  // namespace firn
