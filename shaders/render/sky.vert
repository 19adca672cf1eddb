#version 430 core
// A triangle covering the viewport (gl_VertexID 0, 1, 2; no vertex attributes), behind everything.
void main() {
  vec2 corner = vec2(float((gl_VertexID & 1) << 2), float((gl_VertexID & 2) << 1)) - 1.0;
  gl_Position = vec4(corner, 1.0, 1.0);
}
