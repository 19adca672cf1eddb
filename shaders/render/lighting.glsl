// The light of every picture, in world space (y up): a key light (a small disc, the sun, whose angular
// radius sets the softness of the ground shadows), a cool fill light from the other side, and hemisphere
// ambient light, sky above and ground bounce below. Values are linear radiance; displayColor() maps them to
// the 8-bit sRGB the framebuffer stores.

const vec3 KEY_LIGHT_DIRECTION = normalize(vec3(-0.45, 0.8, 0.4));  // towards the light: upper left, in front
const vec3 KEY_LIGHT_RADIANCE = vec3(1.05, 0.98, 0.88);    // warm sunlight
// ≈ 3.4°, seven times the sun's: soft enough that the shadow of one particle is a blur, not a speck.
const float KEY_LIGHT_ANGULAR_RADIUS_RAD = 0.06;
const vec3 FILL_LIGHT_DIRECTION = normalize(vec3(0.6, 0.22, 0.64));  // right, low, in front
const vec3 FILL_LIGHT_RADIANCE = vec3(0.16, 0.20, 0.27);
const vec3 SKY_AMBIENT = vec3(0.30, 0.38, 0.52);     // from straight above
const vec3 GROUND_AMBIENT = vec3(0.16, 0.15, 0.14);  // bounced from below

const vec3 SKY_ZENITH = vec3(0.05, 0.13, 0.36);
const vec3 SKY_HORIZON = vec3(0.30, 0.42, 0.62);
const vec3 BELOW_HORIZON = vec3(0.16, 0.17, 0.19);

// Exposure of the exponential tone curve 1 − e^(−k·L): highlights roll off instead of clipping, so lit
// snow stays near-white and keeps its shading.
const float EXPOSURE = 1.8;

// The sky seen along a world direction: a gradient from the horizon up to the zenith, darker below.
vec3 skyRadiance(vec3 directionWorld) {
  float elevation = directionWorld.y;
  if (elevation >= 0.0) return mix(SKY_HORIZON, SKY_ZENITH, sqrt(elevation));
  return mix(SKY_HORIZON, BELOW_HORIZON, sqrt(min(-8.0 * elevation, 1.0)));
}

// Diffuse and specular light leaving a surface of colour `albedo` towards the eye. keyVisibility scales the
// key light (a shadow); wrap > 0 lets light reach past the terminator ("wrap lighting", Green 2004, GPU Gems
// ch. 16), the cheap stand-in for the subsurface scattering that makes snow look soft.
vec3 shade(vec3 albedo, vec3 normal, vec3 toEye, float keyVisibility, float wrap, float specularStrength) {
  float key = max((dot(normal, KEY_LIGHT_DIRECTION) + wrap) / (1.0 + wrap), 0.0) * keyVisibility;
  float fill = max(dot(normal, FILL_LIGHT_DIRECTION), 0.0);
  vec3 ambient = mix(GROUND_AMBIENT, SKY_AMBIENT, 0.5 + 0.5 * normal.y);  // hemisphere lighting
  // Blinn–Phong highlight of the key light, only on the lit side.
  vec3 halfway = normalize(KEY_LIGHT_DIRECTION + toEye);
  float facing = step(0.0, dot(normal, KEY_LIGHT_DIRECTION));
  float specular = specularStrength * facing * pow(max(dot(normal, halfway), 0.0), 40.0) * keyVisibility;
  return albedo * (ambient + KEY_LIGHT_RADIANCE * key + FILL_LIGHT_RADIANCE * fill) + KEY_LIGHT_RADIANCE * specular;
}

// Linear radiance → what an 8-bit sRGB framebuffer stores: tone curve, then the sRGB transfer function
// (as a 1/2.2 power).
vec3 displayColor(vec3 radiance) {
  vec3 toneMapped = 1.0 - exp(-EXPOSURE * max(radiance, vec3(0.0)));
  return pow(toneMapped, vec3(1.0 / 2.2));
}

// sRGB colour (a palette entry, a colour map) → linear albedo.
vec3 linearFromSrgb(vec3 srgb) { return pow(srgb, vec3(2.2)); }
