#include "io/StatsCsv.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace firn {

const char* StatsCsvWriter::header() {
  return "frame,time_s,steps,particles,mass_kg,momentum_x,momentum_y,momentum_z,kinetic_energy_j,wall_ms,"
         "center_of_mass_x,center_of_mass_y,center_of_mass_z,mean_plastic_j,particles_at_walls,active_blocks,"
         "solver_iterations,solver_residual,potential_energy_j,elastic_energy_j,bodies_kinetic_energy_j,"
         "bodies_potential_energy_j,collider_work_j,arrived_energy_j,walls_removed_j,hardening_energy_j,"
         "coupling_energy_j,step_energy_j,dissipated_energy_j,energy_created_j,energy_tolerance_j";
}

StatsCsvWriter::StatsCsvWriter(const std::filesystem::path& path) : file_(path, header(), "stats file") {}

StatsCsvWriter::StatsCsvWriter(const std::filesystem::path& path, int firstFrame)
    : file_(path, header(), "stats file", firstFrame) {}

void StatsCsvWriter::write(const FrameStats& s) {
  const double values[] = {s.massKg,           s.momentumKgMPerS.x,  s.momentumKgMPerS.y,     s.momentumKgMPerS.z,
                           s.kineticEnergyJ,   s.wallMs,             s.centerOfMassM.x,       s.centerOfMassM.y,
                           s.centerOfMassM.z,  s.meanPlasticJ,       s.timeS,                 s.solverResidual,
                           s.potentialEnergyJ, s.elasticEnergyJ,     s.bodiesKineticEnergyJ,  s.bodiesPotentialEnergyJ,
                           s.colliderWorkJ,    s.arrivedEnergyJ,     s.wallsRemovedJ,         s.hardeningEnergyJ,
                           s.couplingEnergyJ,  s.stepEnergyJ,        s.dissipatedEnergyJ,     s.energyCreatedJ,
                           s.energyToleranceJ};
  for (double value : values) {
    if (!std::isfinite(value)) throw std::invalid_argument("stats row for frame " + std::to_string(s.frame) + " is not finite");
  }
  char row[1024];
  std::snprintf(row, sizeof row,
                "%d,%.9g,%llu,%llu,%.9g,%.9g,%.9g,%.9g,%.9g,%.3f,%.9g,%.9g,%.9g,%.9g,%llu,%llu,%d,%.3g,%.9g,%.9g,%.9g,%.9g,"
                "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n",
                s.frame, s.timeS, static_cast<unsigned long long>(s.steps), static_cast<unsigned long long>(s.particles),
                s.massKg, s.momentumKgMPerS.x, s.momentumKgMPerS.y, s.momentumKgMPerS.z, s.kineticEnergyJ, s.wallMs,
                s.centerOfMassM.x, s.centerOfMassM.y, s.centerOfMassM.z, s.meanPlasticJ,
                static_cast<unsigned long long>(s.particlesAtWalls), static_cast<unsigned long long>(s.activeBlocks),
                s.solverIterations, s.solverResidual, s.potentialEnergyJ, s.elasticEnergyJ, s.bodiesKineticEnergyJ,
                s.bodiesPotentialEnergyJ, s.colliderWorkJ, s.arrivedEnergyJ, s.wallsRemovedJ, s.hardeningEnergyJ,
                s.couplingEnergyJ, s.stepEnergyJ, s.dissipatedEnergyJ, s.energyCreatedJ, s.energyToleranceJ);
  file_.append(row);
}

}  // namespace firn
