// The key light's shadow map over the snow's surface: an orthographic view along the light of a box (the
// surface's grid, the host's shadowBox uniforms), each texel holding the depth of the nearest surface towards the
// light. The frame is computed here from KEY_LIGHT_DIRECTION, so the light's direction is written once
// (render/lighting.glsl). Needs render/lighting.glsl.

uniform vec3 shadowBoxMinM;
uniform vec3 shadowBoxMaxM;

// Rows: u and v across the light, w towards it.
mat3 worldToLight() {
  vec3 w = KEY_LIGHT_DIRECTION;
  vec3 u = normalize(cross(abs(w.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0), w));
  return transpose(mat3(u, cross(w, u), w));
}

// The box in light coordinates: the range of its corners along u, v and w.
void shadowBoxInLight(out vec3 lowest, out vec3 highest) {
  mat3 toLight = worldToLight();
  lowest = vec3(1e30);
  highest = vec3(-1e30);
  for (int corner = 0; corner < 8; ++corner) {
    vec3 point = mix(shadowBoxMinM, shadowBoxMaxM, vec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1));
    lowest = min(lowest, toLight * point);
    highest = max(highest, toLight * point);
  }
}

// A point's place in the shadow map: xy in [0, 1] across the light, z its depth in [0, 1] from the box's side
// nearest the light.
vec3 shadowMapCoordinates(vec3 pointM) {
  vec3 lowest, highest;
  shadowBoxInLight(lowest, highest);
  vec3 unit = (worldToLight() * pointM - lowest) / max(highest - lowest, vec3(1e-6));
  return vec3(unit.xy, 1.0 - unit.z);
}

// The depth range the map covers (m): shadow biases are given in metres and divided by it.
float shadowDepthRangeM() {
  vec3 lowest, highest;
  shadowBoxInLight(lowest, highest);
  return max(highest.z - lowest.z, 1e-6);
}
