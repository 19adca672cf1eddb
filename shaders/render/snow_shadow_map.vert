#version 430 core
// The snow's surface drawn into the key light's shadow map (render/shadow_map.glsl), one invocation per index of
// the mesh: gl_VertexID is the vertex's number in the reconstruction's vertex buffer.
// Reads: the surface's vertices. Writes: nothing.
#include "surface/surface_contract.h"
#include "surface/vertices.glsl"
#include "render/lighting.glsl"
#include "render/shadow_map.glsl"

void main() {
  vec3 coordinates = shadowMapCoordinates(vertices[gl_VertexID].positionM.xyz);
  gl_Position = vec4(2.0 * coordinates - 1.0, 1.0);
}
