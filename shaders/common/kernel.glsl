// The particle's stencil: the KERNEL_WIDTH³ nodes its B-spline touches, with per-axis weights and slopes.
// The kernel is chosen per scene by FIRN_KERNEL_CUBIC (64 nodes) or FIRN_KERNEL_QUADRATIC (27 nodes).
#include "common/bspline.glsl"

#if defined(FIRN_KERNEL_CUBIC)
const int KERNEL_WIDTH = 4;
#elif defined(FIRN_KERNEL_QUADRATIC)
const int KERNEL_WIDTH = 3;
#else
#error "define FIRN_KERNEL_CUBIC or FIRN_KERNEL_QUADRATIC"
#endif

// One loop over the KERNEL_NODES nodes rather than three nested ones: compilers unroll small nested loops
// completely, and 64 unrolled copies of a P2G or G2P body cost minutes of JIT compilation on llvmpipe.
const int KERNEL_NODES = KERNEL_WIDTH * KERNEL_WIDTH * KERNEL_WIDTH;
ivec3 stencilOffset(int n) { return ivec3(n % KERNEL_WIDTH, (n / KERNEL_WIDTH) % KERNEL_WIDTH, n / (KERNEL_WIDTH * KERNEL_WIDTH)); }

// Per axis, the weights and slopes of the stencil's nodes baseNode + k, k < KERNEL_WIDTH, as the components of a
// vec4: a component index the same in every invocation is a select on a CPU renderer, where an array index is a
// load per lane.
struct Stencil {
  ivec3 baseNode;                   // first node of the stencil on each axis
  vec4 weightX, weightY, weightZ;   // N(d)
  vec4 slopeX, slopeY, slopeZ;      // dN/dx (1/m)
};

float kernelWeight(float d) {
#if defined(FIRN_KERNEL_CUBIC)
  return cubicBSpline(d);
#else
  return quadraticBSpline(d);
#endif
}

float kernelSlope(float d) {
#if defined(FIRN_KERNEL_CUBIC)
  return cubicBSplineSlope(d);
#else
  return quadraticBSplineSlope(d);
#endif
}

// The first node of the stencil on each axis (the particle's base node: common/blocks.glsl sorts by it).
ivec3 stencilBaseNode(vec3 positionInCells) {
#if defined(FIRN_KERNEL_CUBIC)
  return ivec3(floor(positionInCells)) - 1;
#else
  return ivec3(floor(positionInCells - 0.5));
#endif
}

// Every pass that sorts, bins or transfers a particle must find the same cell for it: a difference and a product by
// the host's 1/h (gpu_contract.h), each exact to the ulp, and precise, as the weights (common/bspline.glsl). A
// division may be 2.5 ulp off and round differently in two programs: a particle within an ulp of a cell's face could
// be binned in one cell and scattered from the next, and P2G by blocks would put its contributions outside their
// rows of the block's region.
vec3 cellCoordinates(vec3 positionM) {
  precise vec3 positionInCells = (positionM - gridOriginM) * cellsPerM;
  return positionInCells;
}

Stencil particleStencil(vec3 positionM) {
  precise vec3 positionInCells = cellCoordinates(positionM);
  precise Stencil stencil;
  stencil.baseNode = stencilBaseNode(positionInCells);
  stencil.weightX = stencil.weightY = stencil.weightZ = vec4(0.0);
  stencil.slopeX = stencil.slopeY = stencil.slopeZ = vec4(0.0);
  for (int k = 0; k < KERNEL_WIDTH; ++k) {
    precise vec3 offsetInCells = positionInCells - vec3(stencil.baseNode + k);
    stencil.weightX[k] = kernelWeight(offsetInCells.x);
    stencil.weightY[k] = kernelWeight(offsetInCells.y);
    stencil.weightZ[k] = kernelWeight(offsetInCells.z);
    precise vec3 slope =
        vec3(kernelSlope(offsetInCells.x), kernelSlope(offsetInCells.y), kernelSlope(offsetInCells.z)) * cellsPerM;
    stencil.slopeX[k] = slope.x;
    stencil.slopeY[k] = slope.y;
    stencil.slopeZ[k] = slope.z;
  }
  return stencil;
}

// w_ip = N(dx) N(dy) N(dz) and its gradient (Stomakhin 2013 eq. 4–5).
float stencilWeight(Stencil s, ivec3 k) {
  precise float w = s.weightX[k.x] * s.weightY[k.y] * s.weightZ[k.z];
  return w;
}
vec3 stencilGradient(Stencil s, ivec3 k) {
  precise vec3 gradient = vec3(s.slopeX[k.x] * s.weightY[k.y] * s.weightZ[k.z],
                               s.weightX[k.x] * s.slopeY[k.y] * s.weightZ[k.z],
                               s.weightX[k.x] * s.weightY[k.y] * s.slopeZ[k.z]);
  return gradient;
}
