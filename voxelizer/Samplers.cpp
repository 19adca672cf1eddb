#include "voxelizer/Samplers.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <random>
#include <stdexcept>
#include <thread>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

namespace firn::voxelizer {
namespace {

constexpr double pi = 3.14159265358979323846;

// Lattice jitter of up to a quarter spacing per axis breaks the lattice's alignment with the grid (which
// otherwise shows as regular patterns in the stress) while keeping neighbours at least half a spacing apart.
constexpr double jitterFraction = 0.25;
// Candidates are generated in batches of this many and their inside tests run in parallel, which bounds the
// memory a large body needs.
constexpr std::size_t candidatesPerBatch = std::size_t{1} << 20;
// Threads take this many candidates at a time, so that costly stretches (near a mesh's surface) spread
// over all of them.
constexpr std::size_t candidatesPerTask = 1024;

// Bridson 2007: k candidates around an active sample before it retires; 30 is the paper's value.
constexpr int poissonCandidatesPerSample = 30;
// r / s for the bulk number density 1/s³, measured (there is no closed form for Bridson's packing): a cube
// of side 60 s filled with every point inside, seeds 1 to 4, about 220,000 samples each, counting those in the
// inner cube of side 50 s (5 s from the faces, beyond the boundary layer below). With r/s = 0.86 the bulk
// density came out 0.9063 ± 0.0007 /s³; density scales as (s/r)³, so r/s = 0.86 · ∛0.9063 = 0.8323, which
// then measured 1.0001 ± 0.0006 /s³.
// Samples also pack more densely against a boundary than in the bulk: the same fills held 0.17 ± 0.01 extra
// samples per s² of face, so a body of volume V and area A gets about V/s³ + 0.17 A/s² samples.
constexpr double poissonRadiusPerSpacing = 0.8323;
constexpr double poissonExtraSamplesPerArea = 0.17;

// A uniform real in [0, 1) from mt19937's raw output, which the C++ standard fixes bit for bit, rather than
// std::uniform_real_distribution, whose output each standard library may compute differently: the same seed
// then gives the same particles with libstdc++, libc++ and MSVC.
double unitInterval(std::mt19937& random) {
  constexpr double twoTo32 = 4294967296.0;
  return static_cast<double>(random()) / twoTo32;
}

// A uniform offset in [-jitterFraction, jitterFraction) spacings.
double jitterM(std::mt19937& random, double spacingM) {
  return (2 * unitInterval(random) - 1) * jitterFraction * spacingM;
}

void checkSpacing(double spacingM) {
  if (!(spacingM > 0) || !std::isfinite(spacingM)) {
    throw std::invalid_argument("samplePoints: the spacing must be positive and finite");
  }
}

// inside(candidate) for every candidate, on all hardware threads. A thread's exception is rethrown here.
std::vector<char> evaluateInside(const std::vector<glm::vec3>& candidatesM, const InsideTest& inside) {
  std::vector<char> isInside(candidatesM.size());
  if (candidatesM.empty()) return isInside;
  std::atomic<std::size_t> nextTask{0};
  const std::size_t taskCount = (candidatesM.size() + candidatesPerTask - 1) / candidatesPerTask;
  const std::size_t threadCount = std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, taskCount);
  std::vector<std::exception_ptr> failures(threadCount);
  auto work = [&](std::size_t thread) {
    try {
      for (std::size_t task = nextTask++; task < taskCount; task = nextTask++) {
        const std::size_t end = std::min(candidatesM.size(), (task + 1) * candidatesPerTask);
        for (std::size_t c = task * candidatesPerTask; c < end; ++c) isInside[c] = inside(glm::dvec3(candidatesM[c]));
      }
    } catch (...) {
      failures[thread] = std::current_exception();
      nextTask = taskCount;
    }
  };
  std::vector<std::thread> threads;
  for (std::size_t thread = 1; thread < threadCount; ++thread) threads.emplace_back(work, thread);
  work(0);
  for (std::thread& thread : threads) thread.join();
  for (const std::exception_ptr& failure : failures) {
    if (failure) std::rethrow_exception(failure);
  }
  return isInside;
}

// The lattice points whose jittered position could land in `box`: indices first to last per axis.
struct LatticeRange {
  glm::dvec3 first;
  glm::dvec3 last;
  double count() const {
    const glm::dvec3 perAxis = last - first + 1.0;
    return perAxis.x * perAxis.y * perAxis.z;
  }
};

LatticeRange latticeRange(const Bounds& box, const SamplingOptions& options) {
  return {glm::floor((box.minM - options.latticeOriginM) / options.spacingM - 0.5 - jitterFraction),
          glm::ceil((box.maxM - options.latticeOriginM) / options.spacingM - 0.5 + jitterFraction)};
}

// Lattice points at origin + (i + 0.5) s, each jittered; this is, draw for draw and operation for operation,
// the sampling Firn's scene bodies have always used, so spheres and boxes keep their particles.
std::vector<glm::dvec3> sampleLattice(const Bounds& box, const InsideTest& inside, const SamplingOptions& options) {
  const double spacingM = options.spacingM;
  const glm::dvec3 originM = options.latticeOriginM;
  const LatticeRange range = latticeRange(box, options);
  constexpr double largestIndex = std::numeric_limits<int>::max() - 1;
  // Written so that a NaN fails too.
  if (!glm::all(glm::greaterThanEqual(range.first, glm::dvec3(-largestIndex))) ||
      !glm::all(glm::lessThanEqual(range.last, glm::dvec3(largestIndex)))) {
    throw std::invalid_argument("samplePoints: the box spans more lattice points than 32-bit indices reach");
  }
  const glm::ivec3 firstIndex(range.first);
  const glm::ivec3 lastIndex(range.last);
  const double candidateCount = range.count();
  double candidatesTested = 0;

  std::mt19937 random(options.seed);
  std::vector<glm::dvec3> pointsM;
  std::vector<glm::vec3> candidatesM;
  candidatesM.reserve(candidatesPerBatch);
  auto keepInsideCandidates = [&] {
    const std::vector<char> isInside = evaluateInside(candidatesM, inside);
    for (std::size_t c = 0; c < candidatesM.size(); ++c) {
      if (isInside[c]) pointsM.emplace_back(candidatesM[c]);
    }
    if (pointsM.size() > options.maxPoints) throw TooManySamples(options.maxPoints);
    candidatesTested += double(candidatesM.size());
    if (options.progress) options.progress(candidatesTested / candidateCount);
    candidatesM.clear();
  };
  for (int k = firstIndex.z; k <= lastIndex.z; ++k) {
    for (int j = firstIndex.y; j <= lastIndex.y; ++j) {
      for (int i = firstIndex.x; i <= lastIndex.x; ++i) {
        // Every lattice point draws, kept or not, so the sequence is fixed; separate statements fix the order
        // of the draws (argument evaluation order is unspecified).
        const double jitterXM = jitterM(random, spacingM);
        const double jitterYM = jitterM(random, spacingM);
        const double jitterZM = jitterM(random, spacingM);
        const glm::dvec3 latticePointM = originM + (glm::dvec3(i, j, k) + 0.5) * spacingM;
        candidatesM.emplace_back(latticePointM + glm::dvec3(jitterXM, jitterYM, jitterZM));
        if (candidatesM.size() == candidatesPerBatch) keepInsideCandidates();
      }
    }
  }
  keepInsideCandidates();
  return pointsM;
}

// Bridson 2007's background grid: cells of side c = r/√3 hold at most one sample each, and every sample within
// r of a point lies in the 5³ cells around the point's own (r = √3 c < 2c).
class BackgroundGrid {
 public:
  BackgroundGrid(const Bounds& box, double radiusM)
      : originM_(box.minM), cellSizeM_(radiusM / std::sqrt(3.0)), radiusSquaredM2_(radiusM * radiusM) {
    // Half-open cells [i c, (i + 1) c) up to and including the box's far faces.
    const glm::dvec3 cellsReal = glm::floor((box.maxM - box.minM) / cellSizeM_) + 1.0;
    if (cellsReal.x * cellsReal.y * cellsReal.z > static_cast<double>(std::numeric_limits<std::int32_t>::max())) {
      throw std::invalid_argument("samplePoints: the box holds too many Poisson-disk grid cells for the spacing");
    }
    cells_ = glm::ivec3(cellsReal);
    sampleInCell_.assign(static_cast<std::size_t>(cells_.x) * cells_.y * cells_.z, empty);
    // Nearest cells first, so that a candidate too close to a sample (most are) is rejected early. The eight
    // corner cells (±2, ±2, ±2) are left out: they are at least √3 c = r away.
    for (int k = -2; k <= 2; ++k) {
      for (int j = -2; j <= 2; ++j) {
        for (int i = -2; i <= 2; ++i) {
          if (std::abs(i) == 2 && std::abs(j) == 2 && std::abs(k) == 2) continue;
          neighbourOffsets_.emplace_back(i, j, k);
        }
      }
    }
    auto gapSquared = [](const glm::ivec3& offset) {
      const glm::ivec3 gap = glm::max(glm::abs(offset) - 1, glm::ivec3(0));
      return gap.x * gap.x + gap.y * gap.y + gap.z * gap.z;
    };
    std::stable_sort(neighbourOffsets_.begin(), neighbourOffsets_.end(),
                     [&](const glm::ivec3& a, const glm::ivec3& b) { return gapSquared(a) < gapSquared(b); });
  }

  bool hasSampleWithinRadius(const glm::dvec3& pointM, const std::vector<glm::dvec3>& samplesM) const {
    const glm::ivec3 cell = cellOf(pointM);
    for (const glm::ivec3& offset : neighbourOffsets_) {
      const glm::ivec3 neighbour = cell + offset;
      if (glm::any(glm::lessThan(neighbour, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(neighbour, cells_))) {
        continue;
      }
      const std::int32_t sample = sampleInCell_[flatIndex(neighbour)];
      if (sample == empty) continue;
      const glm::dvec3 offsetM = samplesM[static_cast<std::size_t>(sample)] - pointM;
      if (glm::dot(offsetM, offsetM) < radiusSquaredM2_) return true;
    }
    return false;
  }

  void insert(const glm::dvec3& pointM, std::size_t sample) {
    sampleInCell_[flatIndex(cellOf(pointM))] = static_cast<std::int32_t>(sample);
  }

 private:
  static constexpr std::int32_t empty = -1;

  // Clamped against rounding at the faces.
  glm::ivec3 cellOf(const glm::dvec3& pointM) const {
    return glm::clamp(glm::ivec3(glm::floor((pointM - originM_) / cellSizeM_)), glm::ivec3(0), cells_ - 1);
  }
  std::size_t flatIndex(const glm::ivec3& cell) const {
    return (static_cast<std::size_t>(cell.z) * cells_.y + cell.y) * cells_.x + cell.x;
  }

  glm::dvec3 originM_;
  double cellSizeM_;
  double radiusSquaredM2_;
  glm::ivec3 cells_;
  std::vector<std::int32_t> sampleInCell_;
  std::vector<glm::ivec3> neighbourOffsets_;
};

// Bridson 2007, "Fast Poisson disk sampling in arbitrary dimensions", in 3D and restricted to `inside`. The
// paper grows the set from one random seed; a shape may have several disconnected parts, so growth starts
// again from every point of a coarse lattice (spacing 2r) that is inside and not yet within r of a sample.
std::vector<glm::dvec3> samplePoissonDisk(const Bounds& box, const InsideTest& inside,
                                          const SamplingOptions& options) {
  const double radiusM = poissonDiskRadiusM(options.spacingM);
  BackgroundGrid grid(box, radiusM);
  std::mt19937 random(options.seed);
  std::vector<glm::dvec3> samplesM;
  std::vector<std::size_t> active;

  // Candidates are rounded to float first, so the distances checked are those between the returned points.
  auto accept = [&](const glm::dvec3& candidateM) {
    if (glm::any(glm::lessThan(candidateM, box.minM)) || glm::any(glm::greaterThan(candidateM, box.maxM))) {
      return false;
    }
    if (grid.hasSampleWithinRadius(candidateM, samplesM) || !inside(candidateM)) return false;
    if (samplesM.size() == options.maxPoints) throw TooManySamples(options.maxPoints);
    grid.insert(candidateM, samplesM.size());
    active.push_back(samplesM.size());
    samplesM.push_back(candidateM);
    return true;
  };

  const double seedSpacingM = 2 * radiusM;
  const glm::ivec3 seedCount(glm::max(glm::ceil((box.maxM - box.minM) / seedSpacingM), glm::dvec3(1.0)));
  for (int k = 0; k < seedCount.z; ++k) {
    if (options.progress) options.progress(double(k) / seedCount.z);
    for (int j = 0; j < seedCount.y; ++j) {
      for (int i = 0; i < seedCount.x; ++i) {
        const glm::vec3 seedM(box.minM + (glm::dvec3(i, j, k) + 0.5) * seedSpacingM);
        if (!accept(glm::dvec3(seedM))) continue;
        // Bridson's step 2: pick a random active sample, try k candidates uniform in the shell between r and
        // 2r around it; accept the first that is at least r from every sample, or retire it if none is.
        while (!active.empty()) {
          const std::size_t slot =
              std::min(active.size() - 1, static_cast<std::size_t>(unitInterval(random) * active.size()));
          const glm::dvec3 centerM = samplesM[active[slot]];
          bool found = false;
          for (int attempt = 0; attempt < poissonCandidatesPerSample && !found; ++attempt) {
            // Radius by inverting the shell's volume fraction, (ρ³ − r³) / (8r³ − r³) = u; direction uniform on
            // the sphere (Archimedes: z uniform in [−1, 1], azimuth uniform).
            const double shellRadiusM = radiusM * std::cbrt(1 + 7 * unitInterval(random));
            const double z = 2 * unitInterval(random) - 1;
            const double azimuthRad = 2 * pi * unitInterval(random);
            const double planar = std::sqrt(1 - z * z);
            const glm::dvec3 direction(planar * std::cos(azimuthRad), planar * std::sin(azimuthRad), z);
            found = accept(glm::dvec3(glm::vec3(centerM + shellRadiusM * direction)));
          }
          if (!found) {
            active[slot] = active.back();
            active.pop_back();
          }
        }
      }
    }
  }
  return samplesM;
}

}  // namespace

SampleEstimate estimateSamples(const Bounds& box, double volumeM3, double areaM2, const SamplingOptions& options) {
  checkSpacing(options.spacingM);
  const double s = options.spacingM;
  SampleEstimate estimate;
  estimate.points = volumeM3 / (s * s * s);
  // Without the index check sampling makes: a box beyond 32-bit indices has an estimate all the same, which is
  // what tells the caller that it is too large.
  estimate.insideTests = latticeRange(box, options).count();
  if (options.sampler == Sampler::PoissonDisk) {
    estimate.points += poissonExtraSamplesPerArea * areaM2 / (s * s);
    estimate.insideTests += poissonCandidatesPerSample * estimate.points;
  }
  return estimate;
}

double volumePerSampleM3(std::size_t sampleCount, const SamplingOptions& options, const RegionSampler& sampleWith) {
  const double latticeCellM3 = options.spacingM * options.spacingM * options.spacingM;
  if (options.sampler == Sampler::Lattice || sampleCount == 0) return latticeCellM3;
  SamplingOptions lattice = options;
  lattice.sampler = Sampler::Lattice;
  return double(sampleWith(lattice).size()) * latticeCellM3 / double(sampleCount);
}

double poissonDiskRadiusM(double spacingM) {
  checkSpacing(spacingM);
  return poissonRadiusPerSpacing * spacingM;
}

std::vector<glm::dvec3> samplePoints(const Bounds& box, const InsideTest& inside, const SamplingOptions& options) {
  checkSpacing(options.spacingM);
  switch (options.sampler) {
    case Sampler::Lattice:
      return sampleLattice(box, inside, options);
    case Sampler::PoissonDisk:
      return samplePoissonDisk(box, inside, options);
  }
  throw std::invalid_argument("samplePoints: unknown sampler");
}

}  // namespace firn::voxelizer
