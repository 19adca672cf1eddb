// The energy audit (docs/numerics.md, "The energy audit"): the ledger's sums (gpu::EnergyLedger, after the watchdog's
// status in its buffer) of what the particles hold, summed once a frame by audit_energy.comp, and of what the steps
// move in and out of the snow: the work of moving colliders, the kinetic energy the domain walls take from particles,
// the energy the rigid bodies' explicit coupling gives, and what snow's hardening gives the strain it holds. Every
// value is rounded to the ledger's unit on its own and summed as a 64-bit integer, so the sums are exact and do not
// depend on the order of the GPU's additions: a run's energy, like its particles, is the same to the bit on any number
// of processes.
#include "common/fixed64.glsl"
#include "common/watchdog.glsl"

// Whether this invocation counts what its collisions move — the energy flows, the objects' loads, the rigid bodies'
// sums: not at a node that a share of the domain of a lower rank holds too and counts (BlockSlot.auditedElsewhere),
// which the passes over nodes set before they collide, nor in the passes that move the bodies, which every share runs
// alike, but on the first share (StepPipeline::step).
bool countedHere = true;

// Joules as the ledger's units, each as its (low, high) words. A value beyond StepUniforms.particleEnergyLimit, or not
// finite, is left out of the sums and counted (counts.x): the host reads that count as energy beyond the scene's
// bound, which no stable step reaches (sim/EnergyAudit.cpp).
void energyUnits(vec4 joules, out uvec4 low, out ivec4 high) {
  vec4 units = round(joules * energyUnitsPerJ);
  bvec4 beyond = not(lessThanEqual(abs(units), vec4(particleEnergyLimit)));  // NaN too
  if (any(beyond)) atomicAdd(counts.x, 1u);
  splitFixed64(mix(units, vec4(0.0), beyond), low, high);
}

// Adds a node's or a particle's flows (J) to the ledger: x the work of moving colliders, y the kinetic energy the walls
// removed, z the energy the bodies' coupling gave, w the energy snow's hardening gave its elastic strain. Most nodes
// and particles meet nothing and add nothing.
void addEnergyFlows(vec4 flowsJ) {
  if (flowsJ == vec4(0.0) || !countedHere) return;
  uvec4 low;
  ivec4 high;
  energyUnits(flowsJ, low, high);
  FIRN_ADD_FIXED64(flowLow, flowHigh, low, high)
}

// The kinetic energy (J) the domain walls took from a particle of `massKg` whose velocity they turned from
// `before` to `after` (collideWithDomainWalls only ever removes a component moving out).
float wallsRemovedJ(float massKg, vec3 before, vec3 after) {
  return 0.5 * massKg * (dot(before, before) - dot(after, after));
}

// Adds an impulse (kg·m/s) that object i of the collider table gave the snow, and the work (J) it did with it, to the
// object's load (gpu::ObjectLoad): bodies.csv's force and work.
void addObjectLoad(uint i, vec3 impulseKgMPerS, float workJ) {
  if (!countedHere) return;
  // The impulse in 2^−24 of m_ref h per second: a unit that no step's length changes (adaptive steps' do).
  uvec4 low;
  ivec4 high;
  splitFixed64(vec4(round(impulseKgMPerS * (massUnitsPerKg * cellsPerM * 16777216.0)), 0.0), low, high);
  uvec4 workLow;
  ivec4 workHigh;
  energyUnits(vec4(workJ, 0.0, 0.0, 0.0), workLow, workHigh);
  low.w = workLow.x;
  high.w = workHigh.x;
  FIRN_ADD_FIXED64(objectLoads[i].low, objectLoads[i].high, low, high)
}
