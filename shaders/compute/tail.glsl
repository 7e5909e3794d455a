// engine/model/tail.cpp in float (eqs. 9, 10; model.glsl), function for function in its order;
// the reasons are in the C++. tail_opening is in bird.glsl (drawing needs it too), open_tail is
// GpuSpecies::open_tail (layout.cpp).

// eq. 9 in radians: lr^2 / 2 phi (layout.cpp: tail_area_per_radian).
float tail_area(GpuSpecies s, float opening) { return s.tail_area_per_radian * opening; }

struct TailGeometry {
  vec3 position, chord, normal;
};
TailGeometry tail_geometry(GpuSpecies s, float bend, float twist) {
  float pitch = s.tail_incidence + bend;
  vec2 p = sin_cos(pitch), t = sin_cos(twist);
  float cp = p.y, sp = p.x, ct = t.y, st = t.x;
  vec3 trailing = vec3(-cp, ct * sp, st * sp);  // rolled by the twist
  return TailGeometry(vec3(s.tail_hinge_x, 0.0, 0.0) + trailing * s.tail_arm,
                      vec3(cp, -ct * sp, -st * sp), vec3(sp, ct * cp, st * cp));
}
