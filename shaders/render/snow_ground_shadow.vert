#version 430 core
// The ground shadow of the snow's surface, drawn into the ground-shadow texture as the colliders' are
// (collider_shadow.vert): each vertex of the mesh projected along the key light onto the ground. One invocation
// per index of the mesh. Reads: the surface's vertices. Writes: nothing.
#include "surface/surface_contract.h"
#include "surface/vertices.glsl"
#include "render/lighting.glsl"
#include "render/ground.glsl"

void main() { gl_Position = vec4(groundCoordinates(shadowPoint(vertices[gl_VertexID].positionM.xyz)), 0.0, 1.0); }
