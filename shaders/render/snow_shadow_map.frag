#version 430 core
// The depth of the nearest surface towards the key light, in the shadow map's colour (read back with texelFetch
// for filtering by hand: render/snow_surface.frag).
out float lightDepth;

void main() { lightDepth = gl_FragCoord.z; }
