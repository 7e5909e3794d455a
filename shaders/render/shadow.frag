#version 450
// A soft disc, darkest at its centre (blended over the ground).
layout(location = 0) in vec2 in_disc;
layout(location = 1) in float in_alpha;
layout(location = 0) out vec4 out_color;

void main() {
  float r2 = dot(in_disc, in_disc);
  if (r2 >= 1.0) discard;
  float falloff = (1.0 - r2) * (1.0 - r2);
  out_color = vec4(0.05, 0.07, 0.04, in_alpha * falloff);
}
