#version 430 core
// The ground shadow of a sphere or box collider, drawn into the ground-shadow texture: each vertex of the
// collider's mesh is projected along the key light onto the ground (a planar projected shadow, Blinn 1988).
#include "render/lighting.glsl"
#include "render/ground.glsl"

layout(location = 0) in vec3 positionM;  // at rest

uniform mat4 poseMatrix;  // the collider's rigid motion from rest to this frame's time

void main() { gl_Position = vec4(groundCoordinates(shadowPoint(vec3(poseMatrix * vec4(positionM, 1.0)))), 0.0, 1.0); }
