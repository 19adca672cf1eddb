#pragma once
// Sampling bodies into particles, with what it will take known first: each body's particle count estimated
// before anything is sampled, and sampling held to a limit (docs/scene-format.md, Sizes and limits).
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "scene/Scene.h"

namespace firn {

// What sampling one body will take, known before sampling it.
struct BodyEstimate {
  double particles = 0;    // about how many particles it yields
  double insideTests = 0;  // how many candidate positions the sampler tests (its time goes with them)
};

// Spheres and boxes analytically (their volume over s³, plus the surface layer Poisson-disk samples add),
// meshes from their volume on a coarse lattice (voxelizer::estimateVoxelize), points bodies exactly. Takes
// milliseconds for the shapes, and a fraction of a second for a mesh of millions of triangles.
BodyEstimate estimateBody(const Body& body, const GridSpec& grid);
std::vector<BodyEstimate> estimateBodies(const Scene& scene);

// The particle spacing s = cell_size / ∛particles_per_cell of sphere, box and mesh bodies.
double particleSpacingM(const Body& body, const GridSpec& grid);

// The volume of a sphere or box body's shape (m³); 0 for a mesh or a points body, whose samples are their volume.
double shapeVolumeM3(const Body& body);

struct SamplingLimits {
  // All bodies together; sampling a body past it stops at once, as bad input naming the body and `reason`.
  std::size_t maxParticles = 0;
  std::string reason;  // what the limit is, e.g. "the 128 MiB llvmpipe allows per particle buffer"
  // Room made for this many particles before sampling (the estimate), so that their vector does not grow by
  // copying itself, which takes up to three times its size for a moment.
  std::size_t expectedParticles = 0;
  // If set, called now and then with the body being sampled and the fraction of its candidates tested.
  std::function<void(std::size_t body, double fraction)> progress;
};

// sampleBodies (scene/Scene.h) under `limits`. Throws InputError naming the scene file and the body.
std::vector<ParticleSeed> sampleBodies(const Scene& scene, const SamplingLimits& limits);

// How the messages name a body: "<scene file>: bodies[i]".
std::string bodyName(const Scene& scene, std::size_t bodyIndex);

}  // namespace firn
