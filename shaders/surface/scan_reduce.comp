#version 430 core
// A prefix scan's way up (engine/surface/PrefixScan.h): each invocation sums one chunk of SCAN_CHUNK elements
// into the level above. One sequential loop per invocation, no barriers: on llvmpipe a barrier switches every
// lane's coroutine, and a loop of 64 is cheap (docs/platform.md, Timing on llvmpipe).
// It reads the values and writes one sum per chunk.
#include "surface/surface_common.glsl"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

layout(std430, binding = FIRN_BINDING_SCAN_VALUES) readonly buffer ScanValueBuffer { uvec2 values[]; };
layout(std430, binding = FIRN_BINDING_SCAN_SUMS) writeonly buffer ScanSumBuffer { uvec2 sums[]; };

uniform uint elementCount;

void main() {
  uint chunk = invocationIndex();
  uint first = chunk * SCAN_CHUNK;
  if (first >= elementCount) return;
  uint end = min(first + SCAN_CHUNK, elementCount);
  uvec2 sum = uvec2(0u);
  for (uint i = first; i < end; ++i) sum += values[i];
  sums[chunk] = sum;
}
