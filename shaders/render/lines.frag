#version 430 core
// Translucent, unlit lines.
uniform vec4 lineColor;  // sRGB, alpha for blending

out vec4 fragColor;

void main() { fragColor = lineColor; }
