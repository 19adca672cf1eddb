// How snow's surface is lit: a bright, soft diffuse with no highlight. Snow scatters light below its surface,
// blue farthest, so light reaches past the terminator (wrap lighting, wider for blue: Green 2004, GPU Gems
// ch. 16, per colour channel) and a little of the key light diffuses into its shadows. Needs render/lighting.glsl.

const vec3 SNOW_WRAP = vec3(0.30, 0.38, 0.50);             // per channel: blue wraps farthest
const vec3 SNOW_SHADOW_SCATTER = vec3(0.05, 0.09, 0.15);  // the share of the key light reaching shadowed snow

vec3 shadeSnow(vec3 albedo, vec3 normal, float keyVisibility) {
  vec3 key = max((vec3(dot(normal, KEY_LIGHT_DIRECTION)) + SNOW_WRAP) / (1.0 + SNOW_WRAP), vec3(0.0));
  vec3 visibility = mix(vec3(keyVisibility), vec3(1.0), SNOW_SHADOW_SCATTER);
  float fill = max(dot(normal, FILL_LIGHT_DIRECTION), 0.0);
  vec3 ambient = mix(GROUND_AMBIENT, SKY_AMBIENT, 0.5 + 0.5 * normal.y);  // hemisphere lighting
  return albedo * (ambient + KEY_LIGHT_RADIANCE * key * visibility + FILL_LIGHT_RADIANCE * fill);
}
