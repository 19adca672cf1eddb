#version 430 core
// The snow's surface lit as snow (render/snow_lighting.glsl), shadowed by itself through the key light's shadow
// map: percentage-closer filtering (Reeves et al. 1987) over a disc of taps as wide as the key light's penumbra a
// reconstruction cell behind an occluder, so that shadows are soft like the ground's.
#include "render/lighting.glsl"
#include "render/snow_lighting.glsl"
#include "render/shadow_map.glsl"

uniform sampler2D shadowMapDepth;
uniform float shadowBiasM;        // how far behind the nearest surface a point must lie to be in its shadow
uniform float shadowFilterTexels; // radius of the filter disc

in vec3 worldPositionM;
in vec3 worldNormal;
in vec3 albedo;

out vec4 fragColor;

// Twelve taps on a disc (a Vogel spiral: golden-angle steps, radius ∝ √i), the same for every pixel.
const int SHADOW_TAPS = 12;

float keyLightVisibility(vec3 pointM, vec3 normal) {
  // Offset along the normal (towards the light's side) so that the surface does not shadow itself where it
  // faces the light at a grazing angle.
  vec3 coordinates = shadowMapCoordinates(pointM + normal * shadowBiasM);
  vec2 size = vec2(textureSize(shadowMapDepth, 0));
  float bias = shadowBiasM / shadowDepthRangeM();
  float lit = 0.0;
  for (int i = 0; i < SHADOW_TAPS; ++i) {
    float angle = 2.39996323 * float(i);  // the golden angle (rad)
    vec2 offset = shadowFilterTexels * sqrt((float(i) + 0.5) / float(SHADOW_TAPS)) * vec2(cos(angle), sin(angle));
    ivec2 texel = clamp(ivec2(coordinates.xy * size + offset), ivec2(0), ivec2(size) - 1);
    lit += coordinates.z - bias <= texelFetch(shadowMapDepth, texel, 0).r ? 1.0 : 0.0;
  }
  return lit / float(SHADOW_TAPS);
}

void main() {
  vec3 normal = normalize(worldNormal);
  float visibility = dot(normal, KEY_LIGHT_DIRECTION) > -0.5 ? keyLightVisibility(worldPositionM, normal) : 0.0;
  fragColor = vec4(displayColor(shadeSnow(albedo, normal, visibility)), 1.0);
}
