#version 430 core
// Collider surfaces: plane quads, sphere and box meshes, built at time 0 and moved by their translation.
#include "render/view.glsl"

layout(location = 0) in vec3 positionM;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec2 planeCoordinatesM;  // planes: position in the quad's own frame from its centre

uniform vec3 translationM;

out vec3 worldPositionM;
out vec3 worldNormal;
out vec2 surfaceCoordinatesM;

void main() {
  worldPositionM = positionM + translationM;
  worldNormal = normal;
  surfaceCoordinatesM = planeCoordinatesM;
  gl_Position = projectionMatrix * viewMatrix * vec4(worldPositionM, 1.0);
}
