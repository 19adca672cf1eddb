#version 430 core
// The background: the sky seen along each pixel's ray.
#include "render/lighting.glsl"
#include "render/view.glsl"

out vec4 fragColor;

void main() { fragColor = vec4(displayColor(skyRadiance(viewToWorldDirection(viewRayDirection(gl_FragCoord.xy)))), 1.0); }
