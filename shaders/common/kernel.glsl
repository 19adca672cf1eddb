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

struct Stencil {
  ivec3 baseNode;                // first node of the stencil on each axis
  vec3 weight[KERNEL_WIDTH];     // N(d) per axis for the nodes baseNode + k
  vec3 slope[KERNEL_WIDTH];      // dN/dx per axis (1/m)
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

vec3 cellCoordinates(vec3 positionM) { return (positionM - gridOrigin()) / cellSize(); }

Stencil particleStencil(vec3 positionM) {
  vec3 positionInCells = cellCoordinates(positionM);
  Stencil stencil;
  stencil.baseNode = stencilBaseNode(positionInCells);
  for (int k = 0; k < KERNEL_WIDTH; ++k) {
    vec3 offsetInCells = positionInCells - vec3(stencil.baseNode + k);
    stencil.weight[k] = vec3(kernelWeight(offsetInCells.x), kernelWeight(offsetInCells.y), kernelWeight(offsetInCells.z));
    stencil.slope[k] = vec3(kernelSlope(offsetInCells.x), kernelSlope(offsetInCells.y), kernelSlope(offsetInCells.z)) /
                       cellSize();
  }
  return stencil;
}

// w_ip = N(dx) N(dy) N(dz) and its gradient (Stomakhin 2013 eq. 4–5).
float stencilWeight(Stencil s, ivec3 k) { return s.weight[k.x].x * s.weight[k.y].y * s.weight[k.z].z; }
vec3 stencilGradient(Stencil s, ivec3 k) {
  return vec3(s.slope[k.x].x * s.weight[k.y].y * s.weight[k.z].z, s.weight[k.x].x * s.slope[k.y].y * s.weight[k.z].z,
              s.weight[k.x].x * s.weight[k.y].y * s.slope[k.z].z);
}
