#version 450
// A triangle covering the screen; the fragment shader finds the view ray of each pixel.
layout(location = 0) out vec2 out_ndc;
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2) * 2.0 - 1.0;
  out_ndc = p;
  gl_Position = vec4(p, 1.0, 1.0);
}
