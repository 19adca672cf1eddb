#version 430 core
// Lit collider and rigid-body surfaces. Planes carry a checkerboard fixed to the plane, so that a moving plane is
// seen to move, and fade into the sky towards the edges of their finite quad; the ground also receives the key
// light's shadow from the ground-shadow texture. Meshes are drawn from both sides, lit on the side seen.
#include "render/lighting.glsl"
#include "render/view.glsl"
#include "render/ground.glsl"

uniform vec3 albedoSrgb;
uniform vec3 cameraPositionM;
uniform float checkerCellM;    // 0: plain
uniform float fadeHalfSizeM;   // 0: no fade; planes: half the quad's side
uniform int receivesShadow;    // the ground: 1
uniform sampler2D groundShadowOpticalDepth;

in vec3 worldPositionM;
in vec3 worldNormal;
in vec2 surfaceCoordinatesM;

out vec4 fragColor;

const float CHECKER_CONTRAST = 0.12;

// A checkerboard of ±1 box-filtered over the pixel's footprint, so that it fades to its mean (0) instead of
// aliasing into moiré where the cells get smaller than a pixel (Quilez, "filtering procedurals": the
// integral of the square wave is a triangle wave).
float filteredChecker(vec2 coordinates) {
  vec2 width = max(fwidth(coordinates), vec2(1e-6));
  vec2 triangleBefore = abs(fract((coordinates - 0.5 * width) * 0.5) - 0.5);
  vec2 triangleAfter = abs(fract((coordinates + 0.5 * width) * 0.5) - 0.5);
  vec2 squareWave = 2.0 * (triangleBefore - triangleAfter) / width;  // mean of the ±1 wave per axis
  return squareWave.x * squareWave.y;
}

void main() {
  // A back face is seen only where a mesh's winding faces inward (planes' back faces are culled).
  vec3 normal = normalize(gl_FrontFacing ? worldNormal : -worldNormal);
  vec3 toEye = normalize(cameraPositionM - worldPositionM);
  vec3 albedo = linearFromSrgb(albedoSrgb);
  if (checkerCellM > 0.0) albedo *= 1.0 + CHECKER_CONTRAST * filteredChecker(surfaceCoordinatesM / checkerCellM);
  float keyVisibility = 1.0;
  if (receivesShadow != 0) {
    vec2 texel = 0.5 + 0.5 * groundCoordinates(worldPositionM);
    keyVisibility = exp(-texture(groundShadowOpticalDepth, texel).r);
  }
  vec3 radiance = shade(albedo, normal, toEye, keyVisibility, 0.0, 0.04);
  if (fadeHalfSizeM > 0.0) {
    float edge = max(abs(surfaceCoordinatesM.x), abs(surfaceCoordinatesM.y)) / fadeHalfSizeM;
    radiance = mix(radiance, skyRadiance(-toEye), smoothstep(0.6, 1.0, edge));
  }
  fragColor = vec4(displayColor(radiance), 1.0);
}
