// engine/model/tail.cpp in float (eqs. 9, 10; model.glsl); tail_opening is in bird.glsl.

void tail_geometry(GpuSpecies s, float bend, float twist, out vec3 position, out vec3 chord,
                   out vec3 normal) {
  float pitch = s.tail_incidence + bend;
  vec2 p = sin_cos(pitch), t = sin_cos(twist);
  float cp = p.y, sp = p.x, ct = t.y, st = t.x;
  vec3 trailing = vec3(-cp, ct * sp, st * sp);
  position = vec3(s.tail_hinge_x, 0.0, 0.0) + trailing * s.tail_arm;
  chord = vec3(cp, -ct * sp, -st * sp);
  normal = vec3(sp, ct * cp, st * cp);
}
