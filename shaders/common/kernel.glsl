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

// An axis's weights and slopes, N(d_k) and dN/dx (1/m) with d_k = positionInCells − (baseNode + k), each written
// out: a vector's component written at a variable index costs NVIDIA's compiler a chain of branches.
void axisWeights(float positionInCells, int baseNode, out vec4 weight, out vec4 slope) {
  precise vec4 offsetInCells = vec4(positionInCells - float(baseNode), positionInCells - float(baseNode + 1),
                                    positionInCells - float(baseNode + 2), positionInCells - float(baseNode + 3));
  weight = vec4(kernelWeight(offsetInCells.x), kernelWeight(offsetInCells.y), kernelWeight(offsetInCells.z), 0.0);
  precise vec4 slopes =
      vec4(kernelSlope(offsetInCells.x), kernelSlope(offsetInCells.y), kernelSlope(offsetInCells.z), 0.0) * cellsPerM;
#if defined(FIRN_KERNEL_CUBIC)
  weight.w = kernelWeight(offsetInCells.w);
  slopes.w = kernelSlope(offsetInCells.w) * cellsPerM;
#endif
  slope = slopes;
}

Stencil particleStencil(vec3 positionM) {
  precise vec3 positionInCells = cellCoordinates(positionM);
  precise Stencil stencil;
  stencil.baseNode = stencilBaseNode(positionInCells);
  axisWeights(positionInCells.x, stencil.baseNode.x, stencil.weightX, stencil.slopeX);
  axisWeights(positionInCells.y, stencil.baseNode.y, stencil.weightY, stencil.slopeY);
  axisWeights(positionInCells.z, stencil.baseNode.z, stencil.weightZ, stencil.slopeZ);
  return stencil;
}

// w_ip = N(dx) N(dy) N(dz) and its gradient (Stomakhin 2013 eq. 4–5), from the node's weights and slopes per axis.
float weightProduct(float wx, float wy, float wz) {
  precise float w = wx * wy * wz;
  return w;
}
vec3 gradientProduct(float wx, float wy, float wz, float sx, float sy, float sz) {
  precise vec3 gradient = vec3(sx * wy * wz, wx * sy * wz, wx * wy * sz);
  return gradient;
}

// The stencil's node k (an offset from its base node), for loops that fix k.x: the tile passes write each row out.
float stencilWeight(Stencil s, ivec3 k) { return weightProduct(s.weightX[k.x], s.weightY[k.y], s.weightZ[k.z]); }
vec3 stencilGradient(Stencil s, ivec3 k) {
  return gradientProduct(s.weightX[k.x], s.weightY[k.y], s.weightZ[k.z], s.slopeX[k.x], s.slopeY[k.y], s.slopeZ[k.z]);
}

// A walk over the stencil's nodes in the order of stencilOffset (x fastest), for the loops that visit every node in
// one loop: each axis's weights and slopes turn past their first component as its offset steps, so the node's
// are always component x. A variable index would cost NVIDIA's compiler a chain of branches per read (P2G by blocks
// and G2P spent most of their time there); a CPU renderer pays a select either way. Gives stencilWeight's and
// stencilGradient's bits: the same products of the same factors.
struct StencilWalk {
  ivec3 k;                          // the node's offset from the base node
  vec4 weightX, weightY, weightZ;   // turned: component x is the node's
  vec4 slopeX, slopeY, slopeZ;
};

StencilWalk beginStencilWalk(Stencil s) {
  return StencilWalk(ivec3(0), s.weightX, s.weightY, s.weightZ, s.slopeX, s.slopeY, s.slopeZ);
}

// The axis's next node first: KERNEL_WIDTH turns bring the vector back.
vec4 turnAxis(vec4 v) {
#if defined(FIRN_KERNEL_CUBIC)
  return v.yzwx;
#else
  return v.yzxw;
#endif
}

float walkWeight(StencilWalk w) { return weightProduct(w.weightX.x, w.weightY.x, w.weightZ.x); }
vec3 walkGradient(StencilWalk w) {
  return gradientProduct(w.weightX.x, w.weightY.x, w.weightZ.x, w.slopeX.x, w.slopeY.x, w.slopeZ.x);
}

void advanceStencilWalk(inout StencilWalk w) {
  w.weightX = turnAxis(w.weightX);
  w.slopeX = turnAxis(w.slopeX);
  if (++w.k.x < KERNEL_WIDTH) return;
  w.k.x = 0;
  w.weightY = turnAxis(w.weightY);
  w.slopeY = turnAxis(w.slopeY);
  if (++w.k.y < KERNEL_WIDTH) return;
  w.k.y = 0;
  w.weightZ = turnAxis(w.weightZ);
  w.slopeZ = turnAxis(w.slopeZ);
  ++w.k.z;
}
