#version 430 core
// Each particle's linear albedo in the frame's colour mode (render/particle_appearance.glsl), for the surface
// reconstruction to carry onto the snow's surface. One invocation per particle.
// It reads positionMass, velocityVolume, plasticState and kirchhoffStress, and writes the particle colours.
#include "common/particles.glsl"
#include "render/lighting.glsl"
#include "render/particle_appearance.glsl"
#include "common/invocation.glsl"
#include "surface/surface_contract.h"

layout(local_size_x = FIRN_PARTICLE_GROUP_SIZE) in;

layout(std430, binding = FIRN_BINDING_SURFACE_PARTICLE_COLORS) writeonly buffer ParticleColorBuffer {
  vec4 particleColors[];
};

uniform uint coloredParticles;

void main() {
  uint p = invocationIndex();
  if (p >= coloredParticles) return;
  particleColors[p] = vec4(particleAlbedo(p), 1.0);
}
