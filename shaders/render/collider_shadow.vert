#version 430 core
// The ground shadow of a collider's or rigid body's mesh, drawn into the ground-shadow texture: each vertex of the
// mesh is projected along the key light onto the ground (a planar projected shadow, Blinn 1988).
#include "render/lighting.glsl"
#include "render/ground.glsl"

layout(location = 0) in vec3 positionM;  // in the object's frame

uniform mat4 poseMatrix;  // the object's frame at this frame's time

void main() { gl_Position = vec4(groundCoordinates(shadowPoint(vec3(poseMatrix * vec4(positionM, 1.0)))), 0.0, 1.0); }
