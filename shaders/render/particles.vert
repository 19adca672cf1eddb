#version 430 core
// Particles as sphere impostors. One invocation per particle (gl_VertexID), no vertex attributes: the
// particle is read in place from the simulation's buffers and becomes a point sprite just large enough to
// cover its sphere's silhouette; particles.frag ray-traces the sphere inside it.
// Reads: positionMass, velocityVolume, plasticState, kirchhoffStress. Writes: nothing.
#include "common/particles.glsl"
#include "render/lighting.glsl"
#include "render/view.glsl"
#include "render/particle_appearance.glsl"

uniform float maxPointSizePx;  // GL_POINT_SIZE_RANGE's upper end

flat out vec3 sphereCentreView;
flat out float sphereRadiusM;
flat out vec3 albedo;

// Half the extent of a sphere's silhouette along one screen axis, in projected units (lateral / depth),
// measured from the projected centre, which the sprite is centred on. The silhouette's edges are where the
// eye's tangent lines touch the sphere (Mara & McGuire 2013, "2D polyhedral bounds of a clipped,
// perspective-projected 3D sphere"): at angles centre ± asin(r / distance). Off the view axis the
// silhouette is wider than r / depth and lies off-centre, so both edges are measured.
float silhouetteHalfExtent(float lateralM, float depthM, float radiusM) {
  float centreAngle = atan(lateralM, depthM);
  float halfAngle = asin(radiusM / length(vec2(lateralM, depthM)));
  float centre = lateralM / depthM;
  return max(tan(centreAngle + halfAngle) - centre, centre - tan(centreAngle - halfAngle));
}

void main() {
  uint p = uint(gl_VertexID);
  vec4 centreView = viewMatrix * vec4(positionMass[p].xyz, 1.0);
  float radiusM = particleRadiusM(p);
  float depthM = -centreView.z;
  sphereCentreView = centreView.xyz;
  sphereRadiusM = radiusM;
  albedo = particleAlbedo(p);
  // A sphere that reaches the eye's plane has no bounded silhouette: leave it out (clip it away).
  if (depthM <= radiusM || radiusM <= 0.0) {
    gl_Position = vec4(0.0, 0.0, 2.0, 1.0);
    gl_PointSize = 1.0;
    return;
  }
  gl_Position = projectionMatrix * centreView;
  vec2 halfExtentPx = vec2(silhouetteHalfExtent(centreView.x, depthM, radiusM) * projectionMatrix[0][0],
                           silhouetteHalfExtent(centreView.y, depthM, radiusM) * projectionMatrix[1][1]) *
                      0.5 * viewportSizePx;
  // One pixel of margin on each side: the sprite's square is rasterised at pixel centres.
  gl_PointSize = clamp(2.0 * max(halfExtentPx.x, halfExtentPx.y) + 2.0, 1.0, maxPointSizePx);
}
