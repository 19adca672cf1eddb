#version 430 core
// The ground shadow of the particles, drawn into the ground-shadow texture (orthographic over the ground
// quad, see ground.glsl). One invocation per particle: a point sprite where the particle's shadow falls
// along the key light, as large as that shadow's penumbra; particle_shadow.frag adds its optical depth.
// Reads: positionMass, velocityVolume. Writes: nothing.
#include "common/particles.glsl"
#include "render/lighting.glsl"
#include "render/ground.glsl"
#include "render/particle_appearance.glsl"

uniform float shadowTexelSizeM;  // 2 · groundHalfSizeM / texture size
uniform float maxPointSizePx;

flat out float plateauRadiusM;
flat out float outerRadiusM;
flat out float centreOcclusion;
flat out float spriteSizeM;

void main() {
  uint p = uint(gl_VertexID);
  vec3 positionM = positionMass[p].xyz;
  float radiusM = particleRadiusM(p);
  float heightM = heightAboveGround(positionM);
  // A sphere under the ground casts nothing onto it.
  if (heightM < -radiusM || radiusM <= 0.0) {
    gl_Position = vec4(0.0, 0.0, 2.0, 1.0);
    gl_PointSize = 1.0;
    return;
  }
  // The shadow of a sphere of radius r lit by a disc of angular radius θ from a distance ℓ along the light:
  // its silhouette (radius r) blurred by the light's footprint (radius p = ℓ tan θ). Fully dark out to
  // |r − p| when r > p; at the centre the sphere hides the fraction min(1, r² / p²) of the light's disc;
  // nothing beyond r + p.
  // The blur is at least a texel wide, which antialiases the edge of a contact shadow.
  float lightPathM = max(heightM, 0.0) / keyLightCosine();
  float penumbraRadiusM = max(lightPathM * tan(KEY_LIGHT_ANGULAR_RADIUS_RAD), shadowTexelSizeM);
  plateauRadiusM = abs(radiusM - penumbraRadiusM);
  outerRadiusM = radiusM + penumbraRadiusM;
  centreOcclusion = radiusM >= penumbraRadiusM ? 1.0 : (radiusM * radiusM) / (penumbraRadiusM * penumbraRadiusM);
  // On the ground the shadow is stretched by 1 / cos along the light's direction: the sprite covers that.
  float spriteSizePx = clamp(2.0 * outerRadiusM / keyLightCosine() / shadowTexelSizeM + 2.0, 1.0, maxPointSizePx);
  spriteSizeM = spriteSizePx * shadowTexelSizeM;
  gl_Position = vec4(groundCoordinates(shadowPoint(positionM)), 0.0, 1.0);
  gl_PointSize = spriteSizePx;
}
