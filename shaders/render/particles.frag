#version 430 core
// The sphere impostor of one particle: the pixel's eye ray is intersected with the particle's sphere in
// view space; pixels that miss are discarded, hits are lit and write the depth of the sphere's surface, so
// that spheres interpenetrate and meet colliders as real geometry would.
#include "render/lighting.glsl"
#include "render/view.glsl"

// Snow scatters light below its surface; wrap lighting softens the terminator by this much.
const float SNOW_WRAP = 0.35;
const float SNOW_SPECULAR = 0.08;

flat in vec3 sphereCentreView;
flat in float sphereRadiusM;
flat in vec3 albedo;

out vec4 fragColor;

void main() {
  vec3 ray = viewRayDirection(gl_FragCoord.xy);
  // Ray–sphere intersection with the ray from the eye, in the form that keeps its precision for a small
  // sphere far away (Haines et al. 2019, Ray Tracing Gems ch. 7): the discriminant is r² − d², with d the
  // distance from the centre to the ray, instead of the difference of two large squares.
  float along = dot(sphereCentreView, ray);
  vec3 centreToRay = along * ray - sphereCentreView;
  float discriminant = sphereRadiusM * sphereRadiusM - dot(centreToRay, centreToRay);
  if (discriminant < 0.0) discard;
  vec3 hitView = (along - sqrt(discriminant)) * ray;
  gl_FragDepth = windowDepth(hitView);
  vec3 normalWorld = viewToWorldDirection((hitView - sphereCentreView) / sphereRadiusM);
  vec3 toEyeWorld = viewToWorldDirection(-ray);
  fragColor = vec4(displayColor(shade(albedo, normalWorld, toEyeWorld, 1.0, SNOW_WRAP, SNOW_SPECULAR)), 1.0);
}
