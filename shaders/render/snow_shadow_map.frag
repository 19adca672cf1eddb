#version 430 core
// The depth of the nearest surface towards the key light, in the shadow map's colour (read back with texelFetch
// for filtering by hand: render/snow_surface.frag). Clamped as the depth test clamps it: objects are drawn with
// depth clamping on (render/object_shadow_map.vert), which need not bound gl_FragCoord.z.
out float lightDepth;

void main() { lightDepth = clamp(gl_FragCoord.z, 0.0, 1.0); }
