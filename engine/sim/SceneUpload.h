#pragma once
// The scene as the GPU stores it: the collider table, the particle records of new particles, and the fingerprint
// that ties a checkpoint to the scene it came from. (The material table is gpu/Materials.h's.)
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gpu/GpuLayout.h"
#include "gpu/Materials.h"
#include "scene/Scene.h"
#include "scene/SceneObjects.h"

namespace firn {

// The field buffer (common/colliders.glsl: a buffer texture of floats): the signed distance field of each mesh
// collider and mesh body, baked once from its placed mesh (voxelizer/DistanceField.h) on its FieldLattice
// (scene/FieldLattice.h), and each rigid body's contact probes; and where each one's lie in it.
struct ColliderFields {
  struct Field {
    int first = -1;                     // the first sample, −1 for none
    glm::ivec3 samples{0};              // per axis
    glm::dvec3 originFromPivotM{0.0};   // sample (0, 0, 0) in the shape's rest frame, from its pivot
    double spacingM = 0;
    double steepestSlope = 0;           // of its interpolation (voxelizer::steepestSlope); rigid bodies' only
  };
  std::vector<float> samples;
  std::vector<Field> colliders;           // per scene collider
  std::vector<Field> bodies;              // per rigid body
  std::vector<glm::ivec2> bodyProbes;     // per rigid body: its first float, and its probes (3 floats each)
};
ColliderFields bakeColliderFields(const Scene& scene);

// A rigid body's contact probes in its own frame (integrate_bodies.comp): a sphere's centre (with its radius as the
// contact radius), a box's corners, edges' midpoints and faces' centres, and a mesh's support points in
// kMeshProbeDirections directions spread evenly over the sphere, each vertex once, with its edges' midpoints where
// they are few enough (a coarse mesh: a box's mesh has the box's probes).
constexpr int kMeshProbeDirections = 128;
std::vector<glm::dvec3> bodyProbes(const RigidBody& body);

// One entry per collider, each with its pose at the start of the segment of its motion that holds `timeS`
// (colliderPose): the GPU advances it rigidly from there.
std::vector<gpu::ColliderParams> colliderEntries(const Scene& scene, const ColliderFields& fields, double timeS);

// The whole table: colliderEntries, then one entry per rigid body at its initial state; at least one (zeroed) so the
// binding is always a valid buffer.
std::vector<gpu::ColliderParams> buildColliderTable(const Scene& scene, const ColliderFields& fields, double timeS);

// A rigid body's entry in the collider table with its frame at `pose` (SceneObjects.h): its shape and motion, which
// the snow's passes meet.
gpu::ColliderParams rigidBodyEntry(const RigidBody& body, const ColliderFields& fields, std::size_t index,
                                   const ObjectPose& pose, double timeS);
// Its record in the bodies' buffer (gpu::BodyRecord): its mass, probes, inertia and angular momentum at `pose`, the
// solves' members empty.
gpu::BodyRecord rigidBodyRecord(const RigidBody& body, const ColliderFields& fields, std::size_t index,
                                const ObjectPose& pose);
// Every body's record at its initial state; at least one (zeroed) so the binding is always a valid buffer.
std::vector<gpu::BodyRecord> buildBodyRecords(const Scene& scene, const ColliderFields& fields);

// The collider table at a time, rebuilt only when the time changes (particles come grouped by release time).
class ColliderTableAt {
 public:
  ColliderTableAt(const Scene& scene, const ColliderFields& fields) : scene_(scene), fields_(fields) {}
  const std::vector<gpu::ColliderParams>& operator()(double timeS);

 private:
  const Scene& scene_;
  const ColliderFields& fields_;
  double timeS_ = 0;
  std::vector<gpu::ColliderParams> table_;
};

// Where a particle of a scene body starts, given the colliders: one that starts inside a collider (where the
// collider is at the particle's release time) is moved along the collider's outward normal to just outside its
// surface, since the grid's collision response only stops motion into a collider and would leave it inside for
// good. Moving it out of one collider may move it into another: a few passes over them all settle that, or say
// it cannot be done.
struct ColliderEscape {
  glm::vec3 positionM{0.0f};  // where the particle starts: moved out, or where it was sampled
  int collider = -1;          // the first collider it started inside, or −1
  float depthM = 0;           // how deep inside that collider it started
  bool stuck = false;         // inside colliders still after the passes, or moved out of the grid's interior
};
// `colliders` is the table at the seed's release time, `fieldSamples` ColliderFields::samples.
ColliderEscape escapeColliders(const GridSpec& grid, const std::vector<gpu::ColliderParams>& colliders,
                               const std::vector<float>& fieldSamples, const ParticleSeed& seed);

// New particles as their buffers hold them: undeformed, unstressed, at rest relative to their seed velocity, and
// out of the colliders (escapeColliders; particles added while running, bodyIndex −1, are placed as given).
struct ParticleRecords {
  std::vector<glm::vec4> positionMass;    // x (m), m (kg)
  std::vector<glm::vec4> velocityVolume;  // v (m/s), V0 (m³)
  std::vector<gpu::ParticlePlasticState> plastic;
  std::size_t size() const { return positionMass.size(); }
};
// V0 = m / ρ of the particle's material: the volume with "particle_volume": "material_density", and the most a
// particle may take from the grid density otherwise (compute_volumes.comp; docs/algorithm.md, Initial volumes).
ParticleRecords particleRecords(const Scene& scene, const MaterialTable& table, const ColliderFields& fields,
                                const std::vector<ParticleSeed>& seeds);

// The blocks of the grid (BLOCK_WIDTH³ nodes) the particles' stencils reach where they are: how large the block
// pool starts (sim/GpuState.h).
std::size_t blocksReached(const Scene& scene, const std::vector<ParticleSeed>& seeds);

// What a checkpoint must match: the grid, the step, the capacity, the material table, the colliders and rigid bodies
// as they start with their distance fields, and every seed, field by field (ParticleSeed has padding, whose bytes
// are not defined).
std::uint64_t sceneFingerprint(const Scene& scene, std::size_t particleCapacity, const MaterialTable& table,
                               const ColliderFields& fields, const std::vector<ParticleSeed>& seeds);
// The fingerprint as run.json and `firn run --check` print it: 16 hexadecimal digits.
std::string fingerprintHex(std::uint64_t fingerprint);

}  // namespace firn
