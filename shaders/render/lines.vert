#version 430 core
// Thin lines in world space: the domain's bounds.
#include "render/view.glsl"

layout(location = 0) in vec3 positionM;

void main() { gl_Position = projectionMatrix * viewMatrix * vec4(positionM, 1.0); }
