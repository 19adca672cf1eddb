// GPU-side detection of the failures that must stop a run loudly (docs/numerics.md, "The watchdog"): fixed-point
// overflow, non-finite particle state, and particles moving more than a cell per step (CFL). Counting is an atomic
// on a rarely touched buffer; the first event of each kind is recorded by the invocation that claims its slot.
// The same buffer holds the energy audit's ledger and the moving objects' loads after the watchdog's status
// (common/energy.glsl).

layout(std430, binding = FIRN_BINDING_WATCHDOG) coherent buffer WatchdogBuffer {
  FIRN_MEMBERS(FIRN_WATCHDOG_STATUS)
  FIRN_MEMBERS(FIRN_ENERGY_LEDGER)
  ObjectLoad objectLoads[];  // an entry per entry of the collider table
};

void reportOverflow(uint node, uint channel) {
  atomicAdd(overflowCount, 1u);
  if (atomicCompSwap(overflowNode, -1, int(node)) == -1) {
    overflowStep = stepIndex;
    overflowChannel = channel;
  }
}

void reportNonFinite(uint particle) {
  atomicAdd(nonFiniteCount, 1u);
  if (atomicCompSwap(nonFiniteParticle, -1, int(particle)) == -1) nonFiniteStep = stepIndex;
}

void reportCflViolation(uint particle, float cellsPerStep) {
  atomicAdd(cflCount, 1u);
  if (atomicCompSwap(cflParticle, -1, int(particle)) == -1) {
    cflStep = stepIndex;
    cflCellsPerStep = cellsPerStep;
  }
}

// For non-negative floats the order of their bit patterns is their numeric order, so an integer atomicMax
// finds the largest speed.
void reportSpeed(float speedMPerS) { atomicMax(maxSpeedBits, floatBitsToUint(speedMPerS)); }

bool allFinite(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }
bool allFinite(mat3 m) { return allFinite(m[0]) && allFinite(m[1]) && allFinite(m[2]); }
