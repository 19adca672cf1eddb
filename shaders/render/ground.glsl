// The ground: the plane the key light's shadows fall on (the first plane collider facing up, else the
// domain's floor), as a square quad with its own 2-D frame. The ground-shadow texture covers the quad:
// texel (0.5 + 0.5 g) for ground coordinates g in [−1, 1]². Needs render/lighting.glsl.

uniform vec3 groundCentreM;   // centre of the quad at this frame's time
uniform vec3 groundNormal;    // unit, out of the ground
uniform vec3 groundTangentU;  // unit, along the texture's u
uniform vec3 groundTangentV;  // unit, along the texture's v
uniform float groundHalfSizeM;

// Height of a point above the ground plane (m).
float heightAboveGround(vec3 pointM) { return dot(pointM - groundCentreM, groundNormal); }

// Ground coordinates of a point, [−1, 1]² over the quad (the point is first projected onto the plane).
vec2 groundCoordinates(vec3 pointM) {
  vec3 offsetM = pointM - groundCentreM;
  return vec2(dot(offsetM, groundTangentU), dot(offsetM, groundTangentV)) / groundHalfSizeM;
}

// Cosine of the key light's angle to the ground normal (the host picks grounds facing up, so it is > 0).
float keyLightCosine() { return dot(KEY_LIGHT_DIRECTION, groundNormal); }

// Where a point's shadow falls: along the key light onto the ground plane (Blinn 1988, "Me and my (fake)
// shadow"). Points below the ground cast straight down, onto their own footprint.
vec3 shadowPoint(vec3 pointM) {
  float heightM = max(heightAboveGround(pointM), 0.0);
  return pointM - KEY_LIGHT_DIRECTION * (heightM / keyLightCosine());
}
