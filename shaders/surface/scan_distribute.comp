#version 430 core
// A prefix scan's way down (engine/surface/PrefixScan.h): each invocation replaces its chunk of SCAN_CHUNK
// elements by their exclusive prefix sums, starting from the chunk's own offset, which the level above (already
// scanned) holds; the top level, a single chunk, starts from 0.
// It reads and writes the values, and reads the level above's scanned sums.
#include "surface/surface_common.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

layout(std430, binding = FIRN_BINDING_SCAN_VALUES) buffer ScanValueBuffer { uvec2 values[]; };
layout(std430, binding = FIRN_BINDING_SCAN_SUMS) readonly buffer ScanSumBuffer { uvec2 sums[]; };

uniform uint elementCount;
uniform int hasLevelAbove;

void main() {
  uint chunk = invocationIndex();
  uint first = chunk * SCAN_CHUNK;
  if (first >= elementCount) return;
  uint end = min(first + SCAN_CHUNK, elementCount);
  uvec2 running = hasLevelAbove != 0 ? sums[chunk] : uvec2(0u);
  for (uint i = first; i < end; ++i) {
    uvec2 value = values[i];
    values[i] = running;
    running += value;
  }
}
