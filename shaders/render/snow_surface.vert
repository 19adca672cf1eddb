#version 430 core
// The snow's surface, drawn straight from the reconstruction's buffers (engine/surface): an indexed draw of its
// triangles whose vertex shader reads each vertex from the vertex buffer by gl_VertexID, no vertex attributes.
// Reads: the surface's vertices. Writes: nothing.
#include "surface/surface_contract.h"
#include "surface/vertices.glsl"
#include "render/view.glsl"
#include "render/lighting.glsl"

uniform vec3 albedoScaleSrgb;  // the colour of a surface rebuilt without colours; 1 otherwise

out vec3 worldPositionM;
out vec3 worldNormal;
out vec3 albedo;

void main() {
  SurfaceVertex vertex = vertices[gl_VertexID];
  worldPositionM = vertex.positionM.xyz;
  worldNormal = vertex.normal.xyz;
  albedo = vertex.albedo.rgb * linearFromSrgb(albedoScaleSrgb);
  gl_Position = projectionMatrix * viewMatrix * vec4(worldPositionM, 1.0);
}
