#pragma once
// An exclusive prefix sum of uvec2 elements on the GPU, in place: element i becomes the sum of elements 0 … i − 1.
// Chunks of SCAN_CHUNK elements are summed into a level above, recursively until one chunk is left, then each
// level is scanned from the offsets the level above now holds (shaders/surface/scan_reduce.comp,
// scan_distribute.comp). Integer sums: the result does not depend on the order of anything.
#include <cstddef>
#include <vector>

#include "gl/Buffer.h"
#include "gl/ComputePass.h"
#include "gl/ShaderLibrary.h"

namespace firn::surface {

class PrefixScan {
 public:
  PrefixScan(const gl::ShaderLibrary& library, const gl::ShaderOptions& options, int maxWorkGroupsX);

  // Scans the first `count` uvec2 of `values`. Scanning count + 1 elements whose last is 0 leaves the total of
  // the first `count` in the last. `buffers` holds what else the scan's programs declare (the surface's uniforms).
  void run(const gl::Buffer& values, std::size_t count, const gl::BufferBindings& buffers, gl::PassTimer& timer);

 private:
  gl::ComputePass reduce_;
  gl::ComputePass distribute_;
  int maxWorkGroupsX_;
  std::vector<gl::Buffer> levels_;  // the sums of each level above the values, grown as needed
};

}  // namespace firn::surface
