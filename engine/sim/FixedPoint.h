#pragma once
// Fixed-point scales for the P2G sums (docs/numerics.md, Fixed-point atomics). The GPU adds nondimensional values:
// mass in units of the reference particle mass m_ref, momentum and impulse in units of m_ref·h/Δt (a node
// moving one cell per step). Their bound is known from the scene, so the scale 2^k is chosen to fit it in
// int32 with headroom, and every remaining bit is resolution.

#include <cstdint>
#include <vector>

namespace firn {

struct Scene;
struct ParticleSeed;

// A node's mass is about particles-per-cell × m_ref at rest; snow may compress this much before the sums
// run out of range.
constexpr double kFixedPointCompressionMargin = 8.0;
// Momentum per unit mass is a velocity in cells per step, which the CFL condition keeps below 1; this much
// more is allowed before overflow (the watchdog reports CFL violations beyond 1 anyway).
constexpr double kFixedPointVelocityMarginCellsPerStep = 4.0;

struct FixedPointScale {
  double referenceMassKg = 0;
  double momentumUnitKgMPerS = 0;  // m_ref · h / Δt
  int fractionBits = 0;            // k: a nondimensional 1 is stored as 2^k
  // k_H: the semi-implicit solve's 64-bit Hessian product sums store a momentum unit as 2^k_H (solverFractionBits).
  int solverFractionBits = 0;

  // The energy audit's ledger (sim/EnergyAudit.h): its units per joule, a power of two (exact in the GPU's float),
  // and the most units one particle may hold in a sum, so that no sum of all the particles leaves 64 bits.
  double energyUnitsPerJ = 0;
  double particleEnergyLimit = 0;

  double unitsPerValue() const;    // 2^k
  double maxNodeValue() const;     // the largest nondimensional sum int32 holds: 2^(31 − k)
  double resolution() const;       // 2^−k
};

// The semi-implicit solve's Hessian products sum contributions up to (c Δt / h)² times the momentum a P2G node sum
// may reach (c the fastest elastic wave): k_H leaves 64-bit sums room for that, 2^8 more (snow's hardening stiffens
// it), and gives the rest, at most 50 bits, to resolution.
int deriveSolverFractionBits(const FixedPointScale& scale, double waveSpeedMPerS, double cellSizeM, double dtS);

// Throws InputError when the scene's particles per cell leave fewer than 8 bits of resolution.
FixedPointScale deriveFixedPointScale(double referenceMassKg, double maxParticlesPerCell, double cellSizeM, double dtS);

// The scale for a scene and its particles: m_ref the heaviest particle, the densest body's particles per cell.
FixedPointScale fixedPointScaleFor(const Scene& scene, const std::vector<ParticleSeed>& particles);
// The densest body's particles per cell.
double maxParticlesPerCell(const Scene& scene);

// A 64-bit fixed-point sum as the GPU keeps it (common/fixed64.glsl): its low word, unsigned, and its high word.
inline std::int64_t joinFixed64(std::uint32_t low, std::int32_t high) {
  return std::int64_t(std::uint64_t(std::uint32_t(high)) << 32 | std::uint64_t(low));
}

}  // namespace firn
