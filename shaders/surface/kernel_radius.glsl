// A particle's kernel: its rest volume V = m / ρ0 and its support radius R = surface.smoothing · V^(1/3), a
// multiple of its spacing in a body sampled at that volume. Needs common/particles.glsl and surface_common.glsl.

layout(std430, binding = FIRN_BINDING_SURFACE_MATERIALS) readonly buffer SurfaceMaterialBuffer {
  vec4 materialInverseDensity[];  // x: 1 / ρ0 (m³/kg) per entry of the material table
};

float particleRestVolumeM3(uint p) {
  return positionMass[p].w * materialInverseDensity[plasticState[p].materialIndex].x;
}

float kernelRadiusM(float restVolumeM3) { return smoothing * pow(restVolumeM3, 1.0 / 3.0); }
