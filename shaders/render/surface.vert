#version 430 core
// Collider and rigid-body surfaces: plane quads and the objects' meshes (scene/SceneObjects.h), built in their
// object's frame and moved by its pose at this frame's time.
#include "render/view.glsl"

layout(location = 0) in vec3 positionM;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec2 planeCoordinatesM;  // planes: position in the quad's own frame from its centre

uniform mat4 poseMatrix;  // the object's frame at this frame's time

out vec3 worldPositionM;
out vec3 worldNormal;
out vec2 surfaceCoordinatesM;

void main() {
  worldPositionM = vec3(poseMatrix * vec4(positionM, 1.0));
  worldNormal = mat3(poseMatrix) * normal;
  surfaceCoordinatesM = planeCoordinatesM;
  gl_Position = projectionMatrix * viewMatrix * vec4(worldPositionM, 1.0);
}
