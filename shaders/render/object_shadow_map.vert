#version 430 core
// A collider's or rigid body's mesh drawn into the key light's shadow map over the snow's surface
// (render/shadow_map.glsl), so that the object shades the snow. The host clamps depth (GL_DEPTH_CLAMP): an object
// nearer the light than the map's box lands on the box's near side.
#include "render/lighting.glsl"
#include "render/shadow_map.glsl"

layout(location = 0) in vec3 positionM;  // in the object's frame

uniform mat4 poseMatrix;  // the object's frame at this frame's time

void main() {
  vec3 coordinates = shadowMapCoordinates(vec3(poseMatrix * vec4(positionM, 1.0)));
  gl_Position = vec4(2.0 * coordinates - 1.0, 1.0);
}
