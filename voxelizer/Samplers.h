#pragma once
// Filling a region with particle positions: a jittered lattice aligned with the simulation grid, or Poisson-disk
// samples at the same number density. The region is given by an inside test, so the samplers serve analytic
// shapes and meshes alike.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
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
  // Sampling stops with TooManySamples once more points than this lie inside: what the caller can hold, in case
  // the estimate made before sampling (estimateSamples, estimateVoxelize) fell short.
  std::size_t maxPoints = std::numeric_limits<std::size_t>::max();
  // If set, called now and then on the calling thread with the fraction of the candidates tested so far.
  std::function<void(double)> progress;
};

class TooManySamples : public std::runtime_error {
 public:
  explicit TooManySamples(std::size_t maxPoints)
      : std::runtime_error("more than " + std::to_string(maxPoints) + " points"), maxPoints_(maxPoints) {}
  std::size_t maxPoints() const { return maxPoints_; }

 private:
  std::size_t maxPoints_;
};

// What sampling a region will take, known before sampling it.
struct SampleEstimate {
  double points = 0;      // about how many points it yields
  double insideTests = 0; // how many candidates it tests (its time goes with them)
};

// For a region of volume V and surface area A within `box`: V/s³ points on the lattice, V/s³ + 0.17 A/s² with
// Poisson-disk samples (poissonDiskRadiusM); the lattice tests every lattice point of the box, Poisson-disk
// sampling some 30 candidates per sample and the lattice again for the samples' volume (volumePerSampleM3).
SampleEstimate estimateSamples(const Bounds& box, double volumeM3, double areaM2, const SamplingOptions& options);

// The points for which `inside` holds, each rounded to float precision before it is tested (so a position
// stored as float lies in the shape) and returned as that float value.
// Lattice: one candidate per lattice point whose jittered position could land in `box`, jittered by up to a
// quarter spacing per axis; `inside` decides, the box only bounds the candidates.
// Poisson-disk: samples in `box` no closer than r to each other, r chosen for the density 1/s³.
// Both are deterministic for a given seed. Throws std::invalid_argument for a spacing that is not positive and
// finite, or a box too large for the lattice's 32-bit indices; TooManySamples past options.maxPoints.
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
