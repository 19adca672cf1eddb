#pragma once
// Filling a region with particle positions: a jittered lattice aligned with the simulation grid, or Poisson-disk
// samples at the same number density. The region is given by an inside test, so the samplers serve analytic
// shapes and meshes alike.
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "voxelizer/Mesh.h"

namespace firn::voxelizer {

// Must be safe to call from several threads at once (the lattice sampler evaluates it in parallel).
using InsideTest = std::function<bool(const glm::dvec3&)>;

enum class Sampler { Lattice, PoissonDisk };

struct SamplingOptions {
  double spacingM = 0;  // lattice spacing s; Poisson-disk samples come at the same number density 1/s³
  Sampler sampler = Sampler::Lattice;
  std::uint32_t seed = 0x4669726e;  // "Firn" in ASCII: any fixed value, so a scene always gives the same particles
  glm::dvec3 latticeOriginM{0.0};   // lattice points at origin + (i + 0.5) s; Firn passes its grid origin
};

// The points for which `inside` holds, each rounded to float precision before it is tested (so a position
// stored as float lies in the shape) and returned as that float value.
// Lattice: one candidate per lattice point whose jittered position could land in `box`, jittered by up to a
// quarter spacing per axis; `inside` decides, the box only bounds the candidates.
// Poisson-disk: samples in `box` no closer than r to each other, r chosen for the density 1/s³.
// Both are deterministic for a given seed. Throws std::invalid_argument for a spacing that is not positive and
// finite, or a box too large for the lattice's 32-bit indices.
std::vector<glm::dvec3> samplePoints(const Bounds& box, const InsideTest& inside, const SamplingOptions& options);

// The Poisson-disk radius r for lattice spacing s: samples are never closer than r, and their number density
// in the bulk is 1/s³. They pack more densely against the region's boundary, about 0.17 extra samples per s²
// of surface, so a body of volume V and area A gets about V/s³ + 0.17 A/s² samples (+2.6% for a ball of
// radius 20 s): where the total mass matters, give each particle ρV/N rather than ρs³.
double poissonDiskRadiusM(double spacingM);

// The volume each of `sampleCount` samples of a region stands for, so that a body's mass is right whatever the
// sampler: s³ on the lattice; for Poisson-disk samples, which pack a little denser along the surface, the
// lattice's count of the same region × s³ / sampleCount. `sampleWith` fills the region with the options given.
using RegionSampler = std::function<std::vector<glm::dvec3>(const SamplingOptions&)>;
double volumePerSampleM3(std::size_t sampleCount, const SamplingOptions& options, const RegionSampler& sampleWith);

}  // namespace firn::voxelizer
