// A particle's size and colour as drawn: a sphere of the particle's rest volume, coloured by the frame's
// colour mode. Needs common/particles.glsl and render/lighting.glsl.

uniform int colorMode;  // FIRN_COLOR_MODE_*, injected from render::ColorMode
uniform vec4 materialColorSrgb[FIRN_MATERIAL_COUNT];  // rgb: the palette colour of each material
// Per material: x 1 / Young's modulus (1/Pa), to make stress dimensionless; y 1 / rest density (m³/kg).
uniform vec4 materialProperties[FIRN_MATERIAL_COUNT];
uniform float speedScaleMPerS;  // speed at the top of the speed colour map

uint particleMaterial(uint p) { return min(plasticState[p].materialIndex, uint(FIRN_MATERIAL_COUNT - 1)); }

// The sphere of the particle's rest volume V = m / ρ0: r = (3 V / 4π)^(1/3) ≈ 0.62 V^(1/3). A body sampled at
// spacing s has V = s³, so r is a little over half the spacing and neighbours on the jittered lattice overlap
// into a closed surface. (V0 from the grid density would do inside a body, but at its surface the grid sees
// half the mass and doubles V0, and the surface would look swollen.)
float particleRadiusM(uint p) {
  const float PI = 3.14159265;
  float restVolumeM3 = positionMass[p].w * materialProperties[particleMaterial(p)].y;
  return pow(3.0 * max(restVolumeM3, 0.0) / (4.0 * PI), 1.0 / 3.0);
}

// Piecewise-linear colour maps through five sRGB control points at 0, ¼, ½, ¾, 1.
vec3 colorMap(vec3 stops[5], float t) {
  float x = clamp(t, 0.0, 1.0) * 4.0;
  int i = min(int(x), 3);
  return mix(stops[i], stops[i + 1], x - float(i));
}

// Speed: matplotlib's viridis (perceptually uniform, dark = still).
vec3 speedColor(float speedMPerS) {
  vec3 viridis[5] = vec3[5](vec3(0.267, 0.005, 0.329), vec3(0.231, 0.322, 0.545), vec3(0.129, 0.569, 0.549),
                            vec3(0.369, 0.788, 0.384), vec3(0.993, 0.906, 0.144));
  return colorMap(viridis, speedMPerS / speedScaleMPerS);
}

// Plastic volume change J_P on a log scale, so that halving and doubling are equally far from neutral:
// neutral grey at 1, blue when compacted (< 1), red when stretched (> 1), full colour at a factor of 2
// (the ends of Moreland's 2009 cool-warm map). The square root makes the first 10 % of compaction visible.
vec3 plasticColor(float plasticJ) {
  float t = clamp(log(max(plasticJ, 1e-6)) / log(2.0), -1.0, 1.0);
  vec3 neutral = vec3(0.87, 0.87, 0.87);
  vec3 end = t < 0.0 ? vec3(0.230, 0.299, 0.754) : vec3(0.706, 0.016, 0.150);
  return mix(neutral, end, sqrt(abs(t)));
}

// Stress: the Frobenius norm of the Kirchhoff stress τ over Young's modulus E, on a log scale from 1e−4 E
// (a settled heap) to 1e−1 E (a hard impact), through matplotlib's inferno (without its black end, which
// would hide the shading).
vec3 stressColor(mat3 kirchhoffStressPa, float inverseYoungsModulusPerPa) {
  float frobeniusPa = sqrt(dot(kirchhoffStressPa[0], kirchhoffStressPa[0]) +
                           dot(kirchhoffStressPa[1], kirchhoffStressPa[1]) +
                           dot(kirchhoffStressPa[2], kirchhoffStressPa[2]));
  float relative = frobeniusPa * inverseYoungsModulusPerPa;
  float t = (log(max(relative, 1e-12)) / log(10.0) + 4.0) / 3.0;
  vec3 inferno[5] = vec3[5](vec3(0.160, 0.043, 0.330), vec3(0.471, 0.110, 0.427), vec3(0.847, 0.263, 0.290),
                            vec3(0.976, 0.557, 0.035), vec3(0.988, 1.000, 0.643));
  return colorMap(inferno, t);
}

// Linear albedo of particle p in the frame's colour mode.
vec3 particleAlbedo(uint p) {
  uint material = particleMaterial(p);
  vec3 srgb = materialColorSrgb[material].rgb;
  if (colorMode == FIRN_COLOR_MODE_SPEED) srgb = speedColor(length(velocityVolume[p].xyz));
  if (colorMode == FIRN_COLOR_MODE_PLASTIC_COMPRESSION) srgb = plasticColor(plasticState[p].plasticJ);
  if (colorMode == FIRN_COLOR_MODE_STRESS) srgb = stressColor(kirchhoffStress[p], materialProperties[material].x);
  return linearFromSrgb(srgb);
}
