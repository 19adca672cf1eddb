#version 430 core
// One particle's soft shadow on the ground, as optical depth τ = −ln(1 − occlusion). Additive blending sums
// τ over particles, so the ground's key-light visibility e^(−Στ) is the product of the particles'
// transmittances (Beer–Lambert): sparse spray casts a faint shadow, a dense clump a dark one.
#include "render/lighting.glsl"
#include "render/ground.glsl"

// One particle never hides the light completely: this caps its τ at −ln(0.001) ≈ 6.9.
const float MAX_OCCLUSION = 0.999;

flat in float plateauRadiusM;
flat in float outerRadiusM;
flat in float centreOcclusion;
flat in float spriteSizeM;

out float opticalDepth;

void main() {
  // Offset on the ground from the shadow's centre (gl_PointCoord's origin is the sprite's upper left; the
  // texture's v grows upwards).
  vec2 offsetM = vec2(gl_PointCoord.x - 0.5, 0.5 - gl_PointCoord.y) * spriteSizeM;
  // Undo the stretch along the light's direction on the ground, to measure in the shadow's own circle.
  vec2 lightOnGround = vec2(dot(KEY_LIGHT_DIRECTION, groundTangentU), dot(KEY_LIGHT_DIRECTION, groundTangentV));
  float lightOnGroundLength = length(lightOnGround);
  if (lightOnGroundLength > 1e-6) {
    vec2 along = lightOnGround / lightOnGroundLength;
    float alongM = dot(offsetM, along);
    offsetM += along * alongM * (keyLightCosine() - 1.0);
  }
  float distanceM = length(offsetM);
  if (distanceM >= outerRadiusM) discard;
  float occlusion = centreOcclusion * (1.0 - smoothstep(plateauRadiusM, outerRadiusM, distanceM));
  opticalDepth = -log(1.0 - MAX_OCCLUSION * occlusion);
}
