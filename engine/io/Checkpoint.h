#pragma once
// Checkpoints: the complete state of a run (every particle field, the step and time counters, emitter progress)
// in a versioned binary file, so that `firn run --resume FILE` continues bit for bit as if never interrupted.
// The simulation has no random state at run time (the dithered rounding hashes step and position), so nothing
// else is needed.
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace firn {

struct Checkpoint {
  // 2: the block-sparse grid keeps no active region between steps, so a checkpoint holds one buffer fewer.
  // 3: the header lists every buffer's size, and the header and each buffer end in their CRC-32.
  // 4: a mesh collider's entry of the collider table (held with rigid bodies) holds its field's steepest slope.
  // 5: the energy audit's account, and its ledger after the watchdog's status.
  // 6: a collider table's entry holds its rigid body's coupled solve (velocities before it, and its sums).
  // 7: with rigid bodies, their contacts of the last step and their records follow the collider table.
  // 8: a body's dynamics (mass, probes, inertia, momentum, free velocities, the explicit coupling's sums) moved from
  //    its entry of the collider table to its record, and a collider's friction, reach and load flag to `contact`.
  static constexpr std::uint32_t kVersion = 8;
  std::uint64_t sceneFingerprint = 0;  // of the scene and its particles: a checkpoint resumes only its own scene
  std::int32_t frame = 0;              // the frame the state belongs to
  double timeS = 0;
  std::uint64_t steps = 0;
  std::uint64_t particleCount = 0;
  std::uint64_t releasedEmitterParticles = 0;
  double fastestSpeedMPerS = 0;
  // The energy audit's account (sim/EnergyAudit.h, EnergyAccount: packEnergyAccount), as the run kept it: its integer
  // sums, and its values in joules and metres per second.
  std::array<std::int64_t, 10> energyIntegers{};
  std::array<double, 12> energyReals{};
  // Per entry of the collider table: the impulse its last frame gave the snow (x, y, z) and its work since the start,
  // in the units of gpu::ObjectLoad (Simulation::objectLoads); then that frame's duration (s), as the run kept them.
  std::vector<std::int64_t> objectLoads;
  double objectLoadDurationS = 0;
  std::vector<std::string> buffers;    // the GPU buffers' bytes, in the simulation's order
};

// Written through a temporary file and a rename. Throws InputError naming the file if it cannot be written.
void writeCheckpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);
// Throws InputError naming the file for a missing, foreign, wrong-version or truncated file, one that is not a
// regular file, and one whose header or buffer (named by its number) fails its CRC-32. Whether the buffers'
// numbers make sense is the simulation's to check (Simulation::resume).
Checkpoint readCheckpoint(const std::filesystem::path& path);

// FNV-1a over bytes: the fingerprint of a scene's state layout and its initial particles.
std::uint64_t fingerprint(const void* bytes, std::size_t size, std::uint64_t seed = 14695981039346656037ull);

}  // namespace firn
