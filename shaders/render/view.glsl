// The camera of the frame, set by the host on every render program (engine/render/Renderer.cpp), and the
// conversions between pixels, view space and depth that the impostors need.

uniform mat4 viewMatrix;               // world → view (m); a rigid motion
uniform mat4 projectionMatrix;         // view → clip
uniform mat4 inverseProjectionMatrix;  // clip → view
uniform vec2 viewportSizePx;
uniform vec2 viewportOriginPx;         // the viewport's corner in the framebuffer (the window's view beside a panel)

// View-space direction of the ray from the eye through a pixel (fragCoord: gl_FragCoord.xy).
vec3 viewRayDirection(vec2 fragCoord) {
  vec2 ndc = 2.0 * (fragCoord - viewportOriginPx) / viewportSizePx - 1.0;
  vec4 pointOnFarPlane = inverseProjectionMatrix * vec4(ndc, 1.0, 1.0);
  return normalize(pointOnFarPlane.xyz / pointOnFarPlane.w);
}

// The window depth the fixed-function pipeline would give a view-space point: what an impostor writes to
// gl_FragDepth so that it meets triangles and other impostors where the real surface would.
float windowDepth(vec3 pointView) {
  vec4 clip = projectionMatrix * vec4(pointView, 1.0);
  float ndcDepth = clip.z / clip.w;
  return 0.5 * (gl_DepthRange.diff * ndcDepth + gl_DepthRange.near + gl_DepthRange.far);
}

// View space → world space for directions (the inverse of a rotation is its transpose).
vec3 viewToWorldDirection(vec3 directionView) { return transpose(mat3(viewMatrix)) * directionView; }
