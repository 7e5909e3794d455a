#include "render/meshes.h"

#include <array>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace aeroflock::render {
namespace {

using glm::vec2;
using glm::vec3;

constexpr float kPi = 3.14159265f;

void vertex(std::vector<MeshVertex>& out, vec3 p, vec3 n, float part, Tint tint) {
  out.push_back({glm::vec4(p, part), glm::vec4(n, float(tint))});
}

// A triangle with one normal, its face's.
void triangle(std::vector<MeshVertex>& out, vec3 a, vec3 b, vec3 c, float part,
              Tint tint = Tint::plumage) {
  vec3 n = glm::cross(b - a, c - a);
  n = glm::length(n) > 0.0f ? glm::normalize(n) : vec3(0, 1, 0);
  for (const vec3& p : {a, b, c}) vertex(out, p, n, part, tint);
}

void quad(std::vector<MeshVertex>& out, vec3 a, vec3 b, vec3 c, vec3 d, float part) {
  triangle(out, a, b, c, part);
  triangle(out, a, c, d, part);
}

// A point of a flat wing or tail mesh: chord x, span z.
vec3 flat(vec2 xz) { return {xz.x, 0.0f, xz.y}; }

// The body and head as one smooth lathe along x (unit length, -0.5 tail to +0.5 crown, radius in
// units of the body's width), with a beak; normals from the profile's slope.
void body(std::vector<MeshVertex>& out) {
  struct Ring {
    float x, r, y;
  };  // y: the axis raised at the head
  const std::array<Ring, 10> profile = {{{-0.50f, 0.08f, 0.00f},
                                         {-0.38f, 0.26f, 0.00f},
                                         {-0.18f, 0.44f, 0.00f},
                                         {0.02f, 0.50f, 0.00f},
                                         {0.18f, 0.43f, 0.02f},
                                         {0.29f, 0.28f, 0.06f},
                                         {0.35f, 0.27f, 0.09f},
                                         {0.43f, 0.28f, 0.10f},
                                         {0.50f, 0.18f, 0.09f},
                                         {0.54f, 0.09f, 0.08f}}};
  constexpr int kSides = 10;
  auto point = [&](size_t i, int k) {
    const float a = 2.0f * kPi * float(k) / kSides;
    const Ring& r = profile[i];
    return vec3(r.x, r.y + r.r * std::cos(a), r.r * std::sin(a));
  };
  auto normal = [&](size_t i, int k) {
    const size_t lo = i == 0 ? 0 : i - 1, hi = std::min(i + 1, profile.size() - 1);
    const float slope = (profile[hi].r - profile[lo].r) / (profile[hi].x - profile[lo].x);
    const float a = 2.0f * kPi * float(k) / kSides;
    return glm::normalize(vec3(-slope, std::cos(a), std::sin(a)));
  };
  for (size_t i = 0; i + 1 < profile.size(); ++i)
    for (int k = 0; k < kSides; ++k) {
      const std::array<std::pair<size_t, int>, 6> corners = {
          {{i, k}, {i + 1, k}, {i + 1, k + 1}, {i, k}, {i + 1, k + 1}, {i, k + 1}}};
      for (const auto& [ring, side] : corners)
        vertex(out, point(ring, side), normal(ring, side), 0.0f, Tint::plumage);
    }
  // The tail end closed; the beak a cone from the last ring.
  const vec3 rump(-0.52f, 0.0f, 0.0f), tip(0.72f, 0.06f, 0.0f);
  for (int k = 0; k < kSides; ++k) {
    triangle(out, rump, point(0, k + 1), point(0, k), 0.0f);
    triangle(out, point(profile.size() - 1, k), point(profile.size() - 1, k + 1), tip, 0.0f,
             Tint::beak);
  }
}

// The arm: a leading edge along +x, secondaries overlapping to a scalloped trailing edge. Its root
// reaches a quarter of its length in from the shoulder, into the body (the shoulder lies off the
// body's side: the paper's wing starts at box_c / 2 - wing length).
void arm(std::vector<MeshVertex>& out, float part) {
  constexpr int kFeathers = 6;
  for (int i = 0; i < kFeathers; ++i) {
    const float z0 = i == 0 ? -0.25f : float(i) / kFeathers, z1 = float(i + 1) / kFeathers,
                zm = 0.5f * (z0 + z1);
    const float lead0 = 0.5f - 0.04f * z0 * z0, lead1 = 0.5f - 0.04f * z1 * z1;
    quad(out, flat({lead0, z0}), flat({lead1, z1}), flat({-0.42f, z1}), flat({-0.42f, z0}), part);
    triangle(out, flat({-0.42f, z0}), flat({-0.42f, z1}), flat({-0.6f, zm}), part,
             Tint::flight_feathers);
  }
}

// The hand: a plate from the wrist, then five primaries fanned out to the tip (slotted).
void hand(std::vector<MeshVertex>& out, float part) {
  quad(out, flat({0.5f, 0.0f}), flat({0.36f, 0.55f}), flat({-0.44f, 0.55f}), flat({-0.5f, 0.0f}),
       part);
  constexpr int kPrimaries = 5;
  const std::array<vec2, kPrimaries> tips = {
      {{0.12f, 1.0f}, {-0.04f, 0.98f}, {-0.2f, 0.93f}, {-0.36f, 0.85f}, {-0.52f, 0.76f}}};
  for (int i = 0; i < kPrimaries; ++i) {
    const float base_x = 0.36f - 0.8f * (float(i) + 0.5f) / kPrimaries, half = 0.085f;
    const vec2 l(base_x + half, 0.5f), r(base_x - half, 0.5f), tip = tips[size_t(i)];
    const vec2 l2 = glm::mix(l, tip + vec2(half, 0.0f) * 0.8f, 0.7f),
               r2 = glm::mix(r, tip - vec2(half, 0.0f) * 0.8f, 0.7f);
    quad(out, flat(l), flat(l2), flat(r2), flat(r), part);
    triangle(out, flat(l2), flat(tip), flat(r2), part, Tint::flight_feathers);
  }
}

// The tail's fan: x the radius fraction, z the angle fraction of the opening (bird.vert spreads
// it); rectrices with rounded tips.
void tail(std::vector<MeshVertex>& out) {
  constexpr int kFeathers = 6;
  for (int i = 0; i < kFeathers; ++i) {
    const float z0 = -0.5f + float(i) / kFeathers, z1 = z0 + 1.0f / kFeathers,
                zm = 0.5f * (z0 + z1);
    triangle(out, flat({0.0f, 0.0f}), flat({0.88f, z0}), flat({0.88f, z1}), 3.0f);
    triangle(out, flat({0.88f, z0}), flat({1.0f, zm}), flat({0.88f, z1}), 3.0f,
             Tint::flight_feathers);
  }
}

// The legs, part 7: two thin boxes under the body (body units: x along it, z across), y from the
// hip (0) to the foot (1); bird.vert sets how far below the body's centre the feet reach.
void legs(std::vector<MeshVertex>& out) {
  constexpr float kAlong = 0.012f, kAcross = 0.05f;  // half widths: the body is longer than wide
  for (float z : {-0.2f, 0.2f}) {
    const vec3 hip[4] = {{-kAlong, 0.0f, z - kAcross},
                         {kAlong, 0.0f, z - kAcross},
                         {kAlong, 0.0f, z + kAcross},
                         {-kAlong, 0.0f, z + kAcross}};
    for (int k = 0; k < 4; ++k) {
      const vec3 a = hip[k], b = hip[(k + 1) % 4];
      const vec3 n = glm::normalize(vec3(a.x + b.x, 0.0f, a.z + b.z - 2.0f * z));
      const vec3 a1 = a + vec3(0, 1, 0), b1 = b + vec3(0, 1, 0);
      for (const vec3& p : {a, a1, b1, a, b1, b}) vertex(out, p, n, 7.0f, Tint::beak);
    }
  }
}

}  // namespace

std::vector<MeshVertex> bird_mesh() {
  std::vector<MeshVertex> v;
  body(v);
  for (float side : {0.0f, 4.0f}) {  // right, then left
    arm(v, 1.0f + side);
    hand(v, 2.0f + side);
  }
  tail(v);
  legs(v);
  return v;
}

std::vector<MeshVertex> distant_bird_mesh() {
  std::vector<MeshVertex> v;
  for (float side : {0.0f, 4.0f}) {
    triangle(v, flat({0.5f, 0.0f}), flat({0.5f, 1.0f}), flat({-0.5f, 0.0f}), 1.0f + side);
    triangle(v, flat({0.5f, 0.0f}), flat({0.1f, 1.0f}), flat({-0.5f, 0.0f}), 2.0f + side);
  }
  return v;
}

std::vector<MeshVertex> tiny_bird_mesh() {
  std::vector<MeshVertex> v;
  for (float side : {0.0f, 4.0f}) {
    triangle(v, flat({0.5f, 0.0f}), flat({0.1f, 1.0f}), flat({-0.5f, 0.0f}), 1.0f + side);
    v[v.size() - 2].position.w = 2.0f + side;  // the tip on the hand
  }
  return v;
}

std::vector<MeshVertex> box_mesh() {
  std::vector<MeshVertex> v;
  const float x0 = -0.5f, x1 = 0.5f, y0 = 0.0f, y1 = 1.0f, z0 = -0.5f, z1 = 0.5f;
  quad(v, {x0, y1, z0}, {x0, y1, z1}, {x1, y1, z1}, {x1, y1, z0}, 0);  // top
  quad(v, {x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1}, 0);  // bottom
  quad(v, {x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}, 0);  // +z
  quad(v, {x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}, 0);  // -z
  quad(v, {x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1}, 0);  // +x
  quad(v, {x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, {x0, y1, z0}, 0);  // -x
  return v;
}

}  // namespace aeroflock::render
