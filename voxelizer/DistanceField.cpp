#include "voxelizer/DistanceField.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "voxelizer/WindingNumber.h"

// The bake follows Bridson's makelevelset3 (SDFGen; Bridson, "Fluid Simulation for Computer Graphics", 2nd ed.,
// 2015, ch. 4): exact distances in a narrow band around every triangle, then each sample's closest triangle carried
// outward from neighbour to neighbour, the distance to it always computed exactly. Here the propagation is sweeps
// along the lattice's lines (independent lines, so threads share them without changing a byte), a descent over
// the surface at every sample, and relaxation to a fixed point: every sample ends with the closest of its own,
// its six neighbours' and the triangles that share a corner with its own.
// The sign is the generalized winding number's (WindingNumber.h), evaluated at every sample near the surface and,
// away from it, at a few samples of each connected region that the surface cannot cross.

namespace firn::voxelizer {
namespace {

// Samples within this many spacings of a triangle's box get its exact distance. A sample whose nearest triangle
// is at most this far is therefore exact without any propagation, and so is every sample the sign's band holds.
constexpr double bandSpacings = 2;
// The sign's band: samples this many spacings or nearer to the surface have their own winding number. Where a
// triangle crosses the segment between two 6-neighbours, h long, the crossing splits it, so one of the two lies
// within h/2 of the triangle: no two neighbours outside the band have the surface between them. The extra
// hundredth is room for rounding. A winding number near the surface took about 7 µs on the 100,000-triangle
// sphere of distance_field_benchmarks.cpp, so the band is no wider than the argument needs: at a whole spacing
// it held twice the samples.
constexpr double signBandSpacings = 0.51;
// Away from the surface the winding number is probed on the sub-lattice of every probeStride-th sample per axis
// (and at each region's first sample): 1/64 of the samples, few enough that probing costs little next to the
// band's own winding numbers, dense enough that a region reaching through a hole in an open mesh, where w passes
// 0.5, shows probes on both sides of it.
constexpr int probeStride = 4;
// ceil((extent + 2 margin) / spacing) from rounded operands can land one past a whole count (130.0000000001);
// steps are counted after taking this much off, a relative amount far above double rounding and far below a
// step.
constexpr double latticeRoundingSlack = 1e-9;
// A triangle whose sine between ab and ac is below this is handled as its three edges. Ericson's region tests
// subtract products that cancel as the triangle flattens: at a sine s their rounding misplaces a region's border
// by about 1e-16 / s of the triangle's size, so a nearly collinear triangle (s near 1e-16) can send a point to
// the face's region, whose height over a plane spanned by rounding is meaningless. At s = 1e-8 the border errs by
// 1e-8 of the size, and taking the edges instead errs by at most the triangle's width, the same 1e-8: both far
// below the 2^-24 that the field's floats keep.
constexpr double flatTriangleSine = 1e-8;
// Work is handed to threads in chunks of this many samples (or lattice layers' worth, for the band), enough
// that taking a chunk costs nothing next to it.
constexpr std::size_t samplesPerChunk = 4096;

constexpr std::int32_t noTriangle = -1;

bool isFinite(const glm::dvec3& point) {
  return std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z);
}

// Runs task(chunk) for every chunk in [0, chunkCount) on up to threadCount threads (the caller's among them),
// chunks handed out in turn. Tasks write disjoint results that do not depend on which thread ran them, so the
// outcome is the same for any thread count. The first exception a task throws is rethrown here.
template <typename Task>
void forEachChunk(std::size_t chunkCount, unsigned threadCount, const Task& task) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failureMutex;
  const auto work = [&] {
    try {
      for (std::size_t chunk = next++; chunk < chunkCount; chunk = next++) task(chunk);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(failureMutex);
      if (!failure) failure = std::current_exception();
      next = chunkCount;
    }
  };
  std::vector<std::thread> helpers;
  const std::size_t helperCount = std::min<std::size_t>(threadCount, chunkCount) - (chunkCount > 0 ? 1 : 0);
  helpers.reserve(helperCount);
  for (std::size_t t = 0; t < helperCount; ++t) helpers.emplace_back(work);
  work();
  for (std::thread& helper : helpers) helper.join();
  if (failure) std::rethrow_exception(failure);
}

std::size_t chunksOf(std::size_t count, std::size_t perChunk) { return (count + perChunk - 1) / perChunk; }

// What the distance queries need of a triangle, computed once.
struct Triangle {
  glm::dvec3 aM, bM, cM;
  glm::dvec3 abM, acM;
  glm::dvec3 normalM2;          // ab × ac, unnormalized
  double inverseNormalSquared;  // 1 / |ab × ac|², or 0 for a flat one (flatTriangleSine)
};

Triangle makeTriangle(const glm::dvec3& aM, const glm::dvec3& bM, const glm::dvec3& cM) {
  Triangle triangle{aM, bM, cM, bM - aM, cM - aM, glm::cross(bM - aM, cM - aM), 0};
  const double normalSquared = glm::dot(triangle.normalM2, triangle.normalM2);
  const double flatSquared =
      flatTriangleSine * flatTriangleSine * glm::dot(triangle.abM, triangle.abM) * glm::dot(triangle.acM, triangle.acM);
  triangle.inverseNormalSquared = normalSquared > flatSquared ? 1 / normalSquared : 0;
  return triangle;
}

double squaredDistanceToSegment(const glm::dvec3& pointM, const glm::dvec3& startM, const glm::dvec3& endM) {
  const glm::dvec3 alongM = endM - startM;
  const double lengthSquared = glm::dot(alongM, alongM);
  const double fraction =
      lengthSquared > 0 ? std::clamp(glm::dot(pointM - startM, alongM) / lengthSquared, 0.0, 1.0) : 0.0;
  const glm::dvec3 offsetM = pointM - (startM + fraction * alongM);
  return glm::dot(offsetM, offsetM);
}

// The squared distance from p to the closest point of the triangle, by the Voronoi regions of its vertices, edges
// and face (Ericson, "Real-Time Collision Detection", 2005, §5.1.5, ClosestPtPointTriangle). In the face's region
// the distance is p's height over the plane, which loses nothing to barycentric rounding. Every division there
// is by a squared edge length or |ab × ac|², zero only for a degenerate triangle (coincident or collinear
// vertices); those, and nearly collinear ones (flatTriangleSine), are measured by their edges.
double squaredDistance(const glm::dvec3& pointM, const Triangle& triangle) {
  if (triangle.inverseNormalSquared == 0) {
    return std::min({squaredDistanceToSegment(pointM, triangle.aM, triangle.bM),
                     squaredDistanceToSegment(pointM, triangle.bM, triangle.cM),
                     squaredDistanceToSegment(pointM, triangle.cM, triangle.aM)});
  }
  const auto squaredLength = [](const glm::dvec3& v) { return glm::dot(v, v); };
  const glm::dvec3& ab = triangle.abM;
  const glm::dvec3& ac = triangle.acM;
  const glm::dvec3 ap = pointM - triangle.aM;
  const double d1 = glm::dot(ab, ap);
  const double d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return squaredLength(ap);  // vertex a
  const glm::dvec3 bp = pointM - triangle.bM;
  const double d3 = glm::dot(ab, bp);
  const double d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return squaredLength(bp);  // vertex b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return squaredLength(ap - d1 / (d1 - d3) * ab);  // edge ab
  const glm::dvec3 cp = pointM - triangle.cM;
  const double d5 = glm::dot(ab, cp);
  const double d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return squaredLength(cp);  // vertex c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return squaredLength(ap - d2 / (d2 - d6) * ac);  // edge ac
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {  // edge bc
    return squaredLength(bp - (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (triangle.cM - triangle.bM));
  }
  const double height = glm::dot(triangle.normalM2, ap);
  return height * height * triangle.inverseNormalSquared;  // the face
}

// The lattice's samples, their closest triangles so far and the squared distances to them. A candidate replaces
// the current triangle if it is nearer or, as near, has the lower index: the result is then the same whatever
// order candidates come in.
class ClosestTriangles {
 public:
  ClosestTriangles(const DistanceField& lattice, const TriangleMesh& mesh, std::vector<Triangle> triangles)
      : originM_(lattice.originM),
        spacingM_(lattice.spacingM),
        samples_(lattice.samples),
        triangles_(std::move(triangles)),
        closest_(lattice.sampleCount(), noTriangle),
        squaredDistancesM2_(lattice.sampleCount(), std::numeric_limits<double>::infinity()) {
    linkTriangles(mesh);
  }

  std::size_t index(int x, int y, int z) const {
    return (std::size_t(z) * std::size_t(samples_.y) + std::size_t(y)) * std::size_t(samples_.x) + std::size_t(x);
  }
  glm::ivec3 coordinates(std::size_t sample) const {
    const std::size_t row = sample / std::size_t(samples_.x);
    return {int(sample % std::size_t(samples_.x)), int(row % std::size_t(samples_.y)),
            int(row / std::size_t(samples_.y))};
  }
  glm::dvec3 positionM(const glm::ivec3& sample) const { return originM_ + spacingM_ * glm::dvec3(sample); }
  const glm::dvec3& originM() const { return originM_; }
  double spacingM() const { return spacingM_; }
  const glm::ivec3& samples() const { return samples_; }
  std::size_t sampleCount() const { return closest_.size(); }
  const std::vector<Triangle>& triangles() const { return triangles_; }
  std::int32_t closest(std::size_t sample) const { return closest_[sample]; }
  double squaredDistanceM2(std::size_t sample) const { return squaredDistancesM2_[sample]; }

  // The nearer of (squaredDistanceM2, triangle) and `candidate`, measured from `pointM`.
  struct Choice {
    std::int32_t triangle;
    double squaredDistanceM2;
  };
  Choice better(const Choice& current, std::int32_t candidate, const glm::dvec3& pointM) const {
    if (candidate == noTriangle || candidate == current.triangle) return current;
    const double squaredDistanceM2 = squaredDistance(pointM, triangles_[std::size_t(candidate)]);
    if (squaredDistanceM2 < current.squaredDistanceM2 ||
        (squaredDistanceM2 == current.squaredDistanceM2 && candidate < current.triangle)) {
      return {candidate, squaredDistanceM2};
    }
    return current;
  }
  Choice choice(std::size_t sample) const { return {closest_[sample], squaredDistancesM2_[sample]}; }
  void set(std::size_t sample, const Choice& choice) {
    closest_[sample] = choice.triangle;
    squaredDistancesM2_[sample] = choice.squaredDistanceM2;
  }
  // Offers sample `to` the closest triangle of sample `from`.
  void offer(std::size_t from, std::size_t to, const glm::ivec3& toSample) {
    set(to, better(choice(to), closest_[from], positionM(toSample)));
  }
  // Walks the surface from `start` to a triangle no triangle sharing a corner with improves on: the nearest
  // triangle's region can be thinner than the spacing (a narrow face seen edge-on, a sliver), so that no sample
  // near it holds it, while its neighbours on the surface are held nearby.
  Choice descend(Choice start, const glm::dvec3& pointM) const {
    for (std::int32_t from = noTriangle; start.triangle != from;) {
      from = start.triangle;
      for (std::uint32_t at = neighboursBegin_[std::size_t(from)]; at < neighboursBegin_[std::size_t(from) + 1]; ++at) {
        start = better(start, neighbours_[at], pointM);
      }
    }
    return start;
  }

 private:
  // The triangles that share a corner with each triangle, vertices welded by position (a soup that repeats its
  // corners per triangle is still one surface): those of triangle t are neighbours_[neighboursBegin_[t],
  // neighboursBegin_[t + 1]), each once, t itself not among them.
  void linkTriangles(const TriangleMesh& mesh) {
    const std::vector<std::uint32_t> welded = weldByPosition(mesh);
    const std::uint32_t weldedCount =
        welded.empty() ? 0 : *std::max_element(welded.begin(), welded.end()) + 1;
    // The triangles around each welded vertex, v's at aroundBegin[v] to aroundBegin[v + 1].
    std::vector<std::uint32_t> aroundBegin(std::size_t(weldedCount) + 1, 0);
    for (const glm::uvec3& corners : mesh.triangles) {
      for (int corner = 0; corner < 3; ++corner) ++aroundBegin[welded[corners[corner]] + 1];
    }
    for (std::size_t v = 0; v < weldedCount; ++v) aroundBegin[v + 1] += aroundBegin[v];
    std::vector<std::int32_t> around(aroundBegin.back());
    std::vector<std::uint32_t> filled(aroundBegin.begin(), aroundBegin.end() - 1);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      for (int corner = 0; corner < 3; ++corner) around[filled[welded[mesh.triangles[t][corner]]]++] = std::int32_t(t);
    }
    neighboursBegin_.assign(mesh.triangles.size() + 1, 0);
    std::vector<std::int32_t> ring;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      ring.clear();
      for (int corner = 0; corner < 3; ++corner) {
        const std::uint32_t v = welded[mesh.triangles[t][corner]];
        ring.insert(ring.end(), around.begin() + aroundBegin[v], around.begin() + aroundBegin[v + 1]);
      }
      std::sort(ring.begin(), ring.end());
      ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
      for (const std::int32_t other : ring) {
        if (other != std::int32_t(t)) neighbours_.push_back(other);
      }
      neighboursBegin_[t + 1] = std::uint32_t(neighbours_.size());
    }
  }

  std::vector<std::uint32_t> neighboursBegin_;
  std::vector<std::int32_t> neighbours_;
  glm::dvec3 originM_;
  double spacingM_;
  glm::ivec3 samples_;
  std::vector<Triangle> triangles_;
  std::vector<std::int32_t> closest_;
  std::vector<double> squaredDistancesM2_;
};

// (1) Every triangle's exact distance at the samples within bandSpacings of its box. Threads take slabs of
// lattice layers; each walks all triangles and keeps the part of each box inside its slab.
void bakeBand(ClosestTriangles& field, unsigned threadCount) {
  const glm::ivec3 samples = field.samples();
  const std::vector<Triangle>& triangles = field.triangles();
  const glm::dvec3 originM = field.originM();
  const double spacingM = field.spacingM();
  struct SampleBox {
    glm::ivec3 low, high;  // inclusive; empty where low > high
  };
  std::vector<SampleBox> boxes(triangles.size());
  const double bandM = bandSpacings * spacingM;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Triangle& triangle = triangles[t];
    const glm::dvec3 lowM = glm::min(glm::min(triangle.aM, triangle.bM), triangle.cM) - bandM;
    const glm::dvec3 highM = glm::max(glm::max(triangle.aM, triangle.bM), triangle.cM) + bandM;
    boxes[t] = {glm::max(glm::ivec3(glm::ceil((lowM - originM) / spacingM)), glm::ivec3(0)),
                glm::min(glm::ivec3(glm::floor((highM - originM) / spacingM)), samples - 1)};
  }
  const std::size_t layersPerSlab =
      std::max<std::size_t>(1, samplesPerChunk / (std::size_t(samples.x) * std::size_t(samples.y)));
  forEachChunk(chunksOf(std::size_t(samples.z), layersPerSlab), threadCount, [&](std::size_t slab) {
    const int slabLow = int(slab * layersPerSlab);
    const int slabHigh = std::min(samples.z - 1, int((slab + 1) * layersPerSlab) - 1);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      const SampleBox& box = boxes[t];
      const int zLow = std::max(box.low.z, slabLow);
      const int zHigh = std::min(box.high.z, slabHigh);
      for (int z = zLow; z <= zHigh; ++z) {
        for (int y = box.low.y; y <= box.high.y; ++y) {
          for (int x = box.low.x; x <= box.high.x; ++x) {
            const std::size_t sample = field.index(x, y, z);
            field.set(sample, field.better(field.choice(sample), std::int32_t(t), field.positionM({x, y, z})));
          }
        }
      }
    }
  });
}

// (2a) Sweeps along every lattice line, forward then back, x lines then y then z: each sample offers its closest
// triangle to the next along the line. After the three axes every sample has a triangle (every triangle's band
// holds samples) to start the descent from. A sweep's lines are independent, so threads take whole lines.
void sweepLines(ClosestTriangles& field, unsigned threadCount) {
  const glm::ivec3 n = field.samples();
  for (int axis = 0; axis < 3; ++axis) {
    // The lines along `axis` are numbered by their coordinates on the other two axes, (first, second).
    const int firstAxis = axis == 0 ? 1 : 0;
    const int secondAxis = axis == 2 ? 1 : 2;
    const std::size_t lineCount = std::size_t(n[firstAxis]) * std::size_t(n[secondAxis]);
    const std::size_t linesPerChunk = std::max<std::size_t>(1, samplesPerChunk / std::size_t(n[axis]));
    forEachChunk(chunksOf(lineCount, linesPerChunk), threadCount, [&](std::size_t chunk) {
      const std::size_t lineEnd = std::min(lineCount, (chunk + 1) * linesPerChunk);
      for (std::size_t line = chunk * linesPerChunk; line < lineEnd; ++line) {
        glm::ivec3 sample(0);
        sample[firstAxis] = int(line % std::size_t(n[firstAxis]));
        sample[secondAxis] = int(line / std::size_t(n[firstAxis]));
        const auto indexAt = [&](int position) {
          glm::ivec3 at = sample;
          at[axis] = position;
          return field.index(at.x, at.y, at.z);
        };
        for (int position = 1; position < n[axis]; ++position) {
          sample[axis] = position;
          field.offer(indexAt(position - 1), indexAt(position), sample);
        }
        for (int position = n[axis] - 2; position >= 0; --position) {
          sample[axis] = position;
          field.offer(indexAt(position + 1), indexAt(position), sample);
        }
      }
    });
  }
}

// (2b) Descent and relaxation to a fixed point. Every sample first descends the surface (ClosestTriangles::descend)
// from the better of its own triangle and its x predecessor's. Then rounds, Jacobi style so that the order of work
// cannot matter: in the first every sample tries its six neighbours' triangles, in later ones only the neighbours
// of samples that changed in the round before try the changed ones' triangles; an improvement descends. Changes
// are applied together after each round. Each strictly lowers its sample's (distance, index), so the rounds end,
// with no sample improved on by a neighbour's triangle or by a triangle next to its own on the surface.
void relax(ClosestTriangles& field, unsigned threadCount) {
  const glm::ivec3 n = field.samples();
  const std::size_t sampleCount = field.sampleCount();
  struct Update {
    std::size_t sample;
    ClosestTriangles::Choice choice;
  };
  // The best of `sample`'s own triangle and its neighbours' for which `offers` holds, improved by descent if it
  // is not its own (from which it has descended already).
  const auto improve = [&](std::size_t sample, const glm::ivec3& at, const auto& offers) {
    const glm::dvec3 pointM = field.positionM(at);
    const ClosestTriangles::Choice own = field.choice(sample);
    ClosestTriangles::Choice best = own;
    for (int axis = 0; axis < 3; ++axis) {
      for (const int step : {-1, 1}) {
        glm::ivec3 next = at;
        next[axis] += step;
        if (next[axis] < 0 || next[axis] >= n[axis]) continue;
        const std::size_t neighbour = field.index(next.x, next.y, next.z);
        if (offers(neighbour)) best = field.better(best, field.closest(neighbour), pointM);
      }
    }
    return best.triangle != own.triangle ? field.descend(best, pointM) : best;
  };

  std::vector<std::uint8_t> changed(sampleCount, 0);  // in the round before
  std::vector<std::vector<Update>> updates;
  const auto apply = [&] {
    for (const std::vector<Update>& chunkUpdates : updates) {
      for (const Update& update : chunkUpdates) {
        field.set(update.sample, update.choice);
        changed[update.sample] = 1;
      }
    }
  };

  // Every sample descends once, along x lines (independent, so threads take whole lines), each starting from the
  // better of its own triangle and the one its predecessor on the line just descended to: the nearest triangles
  // of neighbouring samples lie close on the surface, so the descent takes a step or two, where descending from
  // the sweeps' triangles, carried unchanged along whole lines, took six on average (on the 100,000-triangle
  // sphere of distance_field_benchmarks.cpp).
  const std::size_t lineCount = std::size_t(n.y) * std::size_t(n.z);
  const std::size_t linesPerChunk = std::max<std::size_t>(1, samplesPerChunk / std::size_t(n.x));
  forEachChunk(chunksOf(lineCount, linesPerChunk), threadCount, [&](std::size_t chunk) {
    const std::size_t lineEnd = std::min(lineCount, (chunk + 1) * linesPerChunk);
    for (std::size_t line = chunk * linesPerChunk; line < lineEnd; ++line) {
      const int y = int(line % std::size_t(n.y));
      const int z = int(line / std::size_t(n.y));
      for (int x = 0; x < n.x; ++x) {
        const std::size_t sample = field.index(x, y, z);
        const glm::dvec3 pointM = field.positionM({x, y, z});
        ClosestTriangles::Choice best = field.choice(sample);
        if (x > 0) best = field.better(best, field.closest(sample - 1), pointM);
        field.set(sample, field.descend(best, pointM));
      }
    }
  });

  // The first round, over the whole lattice by slabs of layers: every neighbour's triangle is offered.
  const std::size_t layerSamples = std::size_t(n.x) * std::size_t(n.y);
  const std::size_t layersPerSlab = std::max<std::size_t>(1, samplesPerChunk / layerSamples);
  updates.assign(chunksOf(std::size_t(n.z), layersPerSlab), {});
  forEachChunk(updates.size(), threadCount, [&](std::size_t slab) {
    const int zEnd = std::min(n.z, int((slab + 1) * layersPerSlab));
    for (int z = int(slab * layersPerSlab); z < zEnd; ++z) {
      for (int y = 0; y < n.y; ++y) {
        for (int x = 0; x < n.x; ++x) {
          const std::size_t sample = field.index(x, y, z);
          const ClosestTriangles::Choice best = improve(sample, {x, y, z}, [](std::size_t) { return true; });
          if (best.triangle != field.closest(sample)) updates[slab].push_back({sample, best});
        }
      }
    }
  });
  apply();

  std::vector<std::uint8_t> queued(sampleCount, 0);
  std::vector<std::size_t> toVisit;
  while (true) {
    // The neighbours of this round's changes, in the order of the changes (which is the lattice's within each
    // chunk, chunks in turn).
    toVisit.clear();
    for (const std::vector<Update>& chunkUpdates : updates) {
      for (const Update& update : chunkUpdates) {
        const glm::ivec3 at = field.coordinates(update.sample);
        for (int axis = 0; axis < 3; ++axis) {
          for (const int step : {-1, 1}) {
            glm::ivec3 next = at;
            next[axis] += step;
            if (next[axis] < 0 || next[axis] >= n[axis]) continue;
            const std::size_t neighbour = field.index(next.x, next.y, next.z);
            if (!queued[neighbour]) {
              queued[neighbour] = 1;
              toVisit.push_back(neighbour);
            }
          }
        }
      }
    }
    if (toVisit.empty()) break;
    for (const std::size_t sample : toVisit) queued[sample] = 0;
    std::vector<std::vector<Update>> nextUpdates(chunksOf(toVisit.size(), samplesPerChunk));
    forEachChunk(nextUpdates.size(), threadCount, [&](std::size_t chunk) {
      const std::size_t end = std::min(toVisit.size(), (chunk + 1) * samplesPerChunk);
      for (std::size_t v = chunk * samplesPerChunk; v < end; ++v) {
        const std::size_t sample = toVisit[v];
        const ClosestTriangles::Choice best =
            improve(sample, field.coordinates(sample), [&](std::size_t neighbour) { return changed[neighbour] != 0; });
        if (best.triangle != field.closest(sample)) nextUpdates[chunk].push_back({sample, best});
      }
    });
    for (const std::vector<Update>& chunkUpdates : updates) {
      for (const Update& update : chunkUpdates) changed[update.sample] = 0;
    }
    updates = std::move(nextUpdates);
    apply();
  }
}

// (3) Which samples are inside: |w| ≥ 0.5 (WindingNumber::inside). Samples within signBandSpacings of the surface
// are evaluated one by one. The others fall into 6-connected regions that no triangle passes through (see
// signBandSpacings), so w is continuous over each region: for a closed mesh, constant. Each region is probed at
// its first sample and at its samples on the sub-lattice of every probeStride-th sample; if every probe agrees
// the region takes their answer, and if not (a region that reaches through a hole in an open mesh from inside to
// outside) every sample of the region is evaluated.
std::vector<std::uint8_t> classifyInside(const ClosestTriangles& field, const WindingNumber& winding,
                                         unsigned threadCount) {
  const glm::ivec3 n = field.samples();
  const std::size_t sampleCount = field.sampleCount();
  const double spacingM = field.spacingM();
  const double signBandSquaredM2 = (signBandSpacings * spacingM) * (signBandSpacings * spacingM);
  std::vector<std::uint8_t> inside(sampleCount, 0);
  const auto evaluate = [&](const std::vector<std::size_t>& which) {
    forEachChunk(chunksOf(which.size(), samplesPerChunk), threadCount, [&](std::size_t chunk) {
      const std::size_t end = std::min(which.size(), (chunk + 1) * samplesPerChunk);
      for (std::size_t w = chunk * samplesPerChunk; w < end; ++w) {
        inside[which[w]] = winding.inside(field.positionM(field.coordinates(which[w])));
      }
    });
  };

  // Regions by flood fill in scan order, so their numbers do not depend on threads; the band is region -1.
  constexpr std::int32_t inBand = -1;
  constexpr std::int32_t unlabelled = -2;
  std::vector<std::int32_t> region(sampleCount, unlabelled);
  std::vector<std::size_t> toEvaluate;  // the band's samples, then the probes
  for (std::size_t sample = 0; sample < sampleCount; ++sample) {
    if (field.squaredDistanceM2(sample) <= signBandSquaredM2) {
      region[sample] = inBand;
      toEvaluate.push_back(sample);
    }
  }
  std::vector<std::size_t> regionFirst;  // each region's first sample in scan order
  std::vector<std::size_t> stack;
  for (std::size_t seed = 0; seed < sampleCount; ++seed) {
    if (region[seed] != unlabelled) continue;
    const auto label = std::int32_t(regionFirst.size());
    regionFirst.push_back(seed);
    toEvaluate.push_back(seed);
    region[seed] = label;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::size_t sample = stack.back();
      stack.pop_back();
      const glm::ivec3 at = field.coordinates(sample);
      if (sample != seed && at.x % probeStride == 0 && at.y % probeStride == 0 && at.z % probeStride == 0) {
        toEvaluate.push_back(sample);
      }
      for (int axis = 0; axis < 3; ++axis) {
        for (const int step : {-1, 1}) {
          glm::ivec3 next = at;
          next[axis] += step;
          if (next[axis] < 0 || next[axis] >= n[axis]) continue;
          const std::size_t neighbour = field.index(next.x, next.y, next.z);
          if (region[neighbour] != unlabelled) continue;
          region[neighbour] = label;
          stack.push_back(neighbour);
        }
      }
    }
  }
  evaluate(toEvaluate);

  // A region whose probes disagree is evaluated in full; the rest take their first sample's answer, which their
  // probes share.
  std::vector<std::uint8_t> regionMixed(regionFirst.size(), 0);
  for (const std::size_t sample : toEvaluate) {
    const std::int32_t label = region[sample];
    if (label != inBand && inside[sample] != inside[regionFirst[std::size_t(label)]])
      regionMixed[std::size_t(label)] = 1;
  }
  std::vector<std::size_t> mixedSamples;
  for (std::size_t sample = 0; sample < sampleCount; ++sample) {
    const std::int32_t label = region[sample];
    if (label == inBand) continue;
    if (regionMixed[std::size_t(label)]) {
      mixedSamples.push_back(sample);
    } else {
      inside[sample] = inside[regionFirst[std::size_t(label)]];
    }
  }
  evaluate(mixedSamples);
  return inside;
}

// Every triangle's features (TriangleFeatures), their normals outward as the baked samples' signs say.
std::vector<TriangleFeatures> triangleFeatures(const TriangleMesh& mesh, const ClosestTriangles& closest,
                                               const std::vector<std::uint8_t>& inside) {
  const std::vector<Triangle>& triangles = closest.triangles();
  // Each sample within a spacing of its triangle's plane, more over it than beside it, votes for the side it lies.
  std::vector<std::int64_t> votes(triangles.size(), 0);
  const double bandM2 = closest.spacingM() * closest.spacingM();
  for (std::size_t sample = 0; sample < closest.sampleCount(); ++sample) {
    const std::int32_t t = closest.closest(sample);
    const double squaredDistanceM2 = closest.squaredDistanceM2(sample);
    if (t == noTriangle || !(squaredDistanceM2 <= bandM2)) continue;
    const Triangle& triangle = triangles[std::size_t(t)];
    if (triangle.inverseNormalSquared == 0) continue;
    const double heightM = glm::dot(closest.positionM(closest.coordinates(sample)) - triangle.aM, triangle.normalM2) *
                           std::sqrt(triangle.inverseNormalSquared);
    if (heightM * heightM < 0.25 * squaredDistanceM2) continue;
    votes[std::size_t(t)] += (heightM < 0) == (inside[sample] != 0) ? 1 : -1;
  }
  // Edges and corners of welded vertices, so that a soup of separate triangles shares its features.
  const std::vector<std::uint32_t> welded = weldByPosition(mesh);
  // Faces wound alike (an edge shared by two, run one way by each) turn together: their votes are summed over the
  // patch, so a face no sample votes for (one whose samples all name a neighbour) turns with the rest.
  std::vector<std::size_t> patch(triangles.size());
  for (std::size_t t = 0; t < patch.size(); ++t) patch[t] = t;
  const auto root = [&](std::size_t t) {
    while (patch[t] != t) t = patch[t] = patch[patch[t]];
    return t;
  };
  const auto edgeKey = [&](std::uint32_t a, std::uint32_t b) {
    return std::uint64_t(std::min(a, b)) << 32 | std::uint64_t(std::max(a, b));
  };
  // Each welded edge's triangles in order, and whether each runs it from its lower point to its higher.
  std::unordered_map<std::uint64_t, std::vector<std::pair<std::int32_t, bool>>> edgeTriangles;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = welded[mesh.triangles[t][k]], b = welded[mesh.triangles[t][(k + 1) % 3]];
      edgeTriangles[edgeKey(a, b)].emplace_back(std::int32_t(t), a < b);
    }
  }
  for (const auto& [edge, run] : edgeTriangles) {
    if (run.size() == 2 && run[0].second != run[1].second) {
      patch[root(std::size_t(run[0].first))] = root(std::size_t(run[1].first));
    }
  }
  std::vector<std::int64_t> patchVotes(triangles.size(), 0);
  for (std::size_t t = 0; t < triangles.size(); ++t) patchVotes[root(t)] += votes[t];
  std::vector<TriangleFeatures> features(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Triangle& triangle = triangles[t];
    const double turn = patchVotes[root(t)] < 0 ? -1.0 : 1.0;
    features[t].face = triangle.normalM2 * (turn * std::sqrt(triangle.inverseNormalSquared));  // 0 for a flat one
  }
  const std::size_t pointCount = welded.empty() ? 0 : *std::max_element(welded.begin(), welded.end()) + 1;
  std::vector<glm::dvec3> cornerSums(pointCount, glm::dvec3(0.0));
  std::unordered_map<std::uint64_t, glm::dvec3> edgeSums;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const glm::uvec3& corners = mesh.triangles[t];
    const glm::dvec3 at[3] = {triangles[t].aM, triangles[t].bM, triangles[t].cM};
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t edge = edgeKey(welded[corners[k]], welded[corners[(k + 1) % 3]]);
      edgeSums[edge] += features[t].face;
      const glm::dvec3 toNext = at[(k + 1) % 3] - at[k], toPrevious = at[(k + 2) % 3] - at[k];
      const double lengths = glm::length(toNext) * glm::length(toPrevious);
      const double angle = lengths > 0 ? std::acos(std::clamp(glm::dot(toNext, toPrevious) / lengths, -1.0, 1.0)) : 0.0;
      cornerSums[welded[corners[k]]] += angle * features[t].face;
    }
  }
  // A feature whose faces cancel (a sheet folded flat, faces of both windings) keeps its own face's normal.
  const auto unit = [](const glm::dvec3& sum, const glm::dvec3& fallback) {
    const double length = glm::length(sum);
    return length > 0 ? sum / length : fallback;
  };
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const glm::uvec3& corners = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t edge = edgeKey(welded[corners[k]], welded[corners[(k + 1) % 3]]);
      features[t].edges[k] = unit(edgeSums[edge], features[t].face);
      for (const auto& [other, forward] : edgeTriangles[edge]) {
        if (other != std::int32_t(t)) {
          features[t].across[k] = other;  // the first other, where more than two share the edge
          break;
        }
      }
      features[t].corners[k] = unit(cornerSums[welded[corners[k]]], features[t].face);
    }
  }
  return features;
}

}  // namespace

glm::dvec3 distanceFieldSamples(const Bounds& meshBox, double spacingM, double marginM) {
  return glm::ceil((meshBox.maxM - meshBox.minM + 2 * marginM) / spacingM * (1 - latticeRoundingSlack)) + 1.0;
}

DistanceField distanceFieldLattice(const Bounds& meshBox, double spacingM, double marginM) {
  if (!(std::isfinite(spacingM) && spacingM > 0)) {
    throw MeshError("distance field: the spacing must be positive and finite, not " + std::to_string(spacingM));
  }
  if (!(std::isfinite(marginM) && marginM > 0)) {
    throw MeshError("distance field: the margin must be positive and finite, not " + std::to_string(marginM));
  }
  if (!isFinite(meshBox.minM) || !isFinite(meshBox.maxM)) {
    throw MeshError("distance field: the mesh's box is not finite");
  }
  DistanceField field;
  field.originM = meshBox.minM - marginM;
  field.spacingM = spacingM;
  const glm::dvec3 samples = distanceFieldSamples(meshBox, spacingM, marginM);
  double sampleCount = 1;
  for (int axis = 0; axis < 3; ++axis) {
    if (!(samples[axis] <= double(std::numeric_limits<int>::max()))) {
      throw MeshError("distance field: more than 2^31 samples along an axis at a spacing of " +
                      std::to_string(spacingM) + " m");
    }
    field.samples[axis] = int(samples[axis]);
    sampleCount *= samples[axis];
  }
  // Sample and triangle indices are std::size_t; the distances' vector must be able to hold them.
  if (!(sampleCount <= double(std::vector<float>().max_size()))) {
    throw MeshError("distance field: too many samples (" + std::to_string(sampleCount) + ") at a spacing of " +
                    std::to_string(spacingM) + " m");
  }
  return field;
}

DistanceField bakeDistanceField(const TriangleMesh& mesh, double spacingM, double marginM) {
  return bakeDistanceField(mesh, spacingM, marginM, 0);
}

DistanceField bakeDistanceField(const TriangleMesh& mesh, double spacingM, double marginM, unsigned threadCount) {
  if (mesh.triangles.empty()) throw MeshError("distance field: the mesh has no triangles");
  // The GPU reads each sample's nearest triangle as a float, exact up to 2^24.
  if (mesh.triangles.size() > std::size_t(1) << 24) {
    throw MeshError("distance field: more than 2^24 (16,777,216) triangles");
  }
  std::vector<Triangle> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const glm::uvec3& corners : mesh.triangles) {
    for (int corner = 0; corner < 3; ++corner) {
      if (corners[corner] >= mesh.vertices.size())
        throw MeshError("distance field: a triangle indexes past the vertices");
      if (!isFinite(mesh.vertices[corners[corner]])) throw MeshError("distance field: a vertex is not finite");
    }
    triangles.push_back(makeTriangle(mesh.vertices[corners.x], mesh.vertices[corners.y], mesh.vertices[corners.z]));
  }
  if (threadCount == 0) threadCount = std::max(1u, std::thread::hardware_concurrency());

  DistanceField field = distanceFieldLattice(bounds(mesh), spacingM, marginM);
  ClosestTriangles closest(field, mesh, std::move(triangles));
  bakeBand(closest, threadCount);
  sweepLines(closest, threadCount);
  relax(closest, threadCount);
  const std::vector<std::uint8_t> inside = classifyInside(closest, WindingNumber(mesh), threadCount);

  field.distancesM.resize(field.sampleCount());
  field.nearestTriangles.resize(field.sampleCount());
  forEachChunk(chunksOf(field.sampleCount(), samplesPerChunk), threadCount, [&](std::size_t chunk) {
    const std::size_t end = std::min(field.sampleCount(), (chunk + 1) * samplesPerChunk);
    for (std::size_t sample = chunk * samplesPerChunk; sample < end; ++sample) {
      const auto distanceM = float(std::sqrt(closest.squaredDistanceM2(sample)));
      field.distancesM[sample] = inside[sample] ? -distanceM : distanceM;
      field.nearestTriangles[sample] = closest.closest(sample);
    }
  });
  field.features = triangleFeatures(mesh, closest, inside);
  return field;
}

double steepestSlope(const DistanceField& field) {
  const glm::ivec3 n = field.samples;
  if (n.x < 2 || n.y < 2 || n.z < 2) return 0;
  double steepest = 0;
  for (int z = 0; z + 1 < n.z; ++z) {
    for (int y = 0; y + 1 < n.y; ++y) {
      for (int x = 0; x + 1 < n.x; ++x) {
        glm::dvec3 largest(0.0);  // the largest difference along each axis over the cell's edges
        for (int a = 0; a < 2; ++a) {
          for (int b = 0; b < 2; ++b) {
            const float alongX = field.at(x + 1, y + a, z + b) - field.at(x, y + a, z + b);
            const float alongY = field.at(x + a, y + 1, z + b) - field.at(x + a, y, z + b);
            const float alongZ = field.at(x + a, y + b, z + 1) - field.at(x + a, y + b, z);
            largest = glm::max(largest, glm::abs(glm::dvec3(alongX, alongY, alongZ)));
          }
        }
        steepest = std::max(steepest, glm::length(largest));
      }
    }
  }
  return steepest / field.spacingM;
}

}  // namespace firn::voxelizer
