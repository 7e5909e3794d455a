#include "render/meshes.h"

#include <array>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace aeroflock::render {
namespace {

using glm::vec3;

// A flat-shaded triangle of part `part`; `detail` triangles are left out of distant birds.
void triangle(std::vector<MeshVertex>& out, vec3 a, vec3 b, vec3 c, float part, bool detail = false) {
  vec3 n = glm::cross(b - a, c - a);
  n = glm::length(n) > 0.0f ? glm::normalize(n) : vec3(0, 1, 0);
  for (const vec3& p : {a, b, c}) out.push_back({glm::vec4(p, part), glm::vec4(n, detail ? 1.0f : 0.0f)});
}

// Two triangles; the second is detail (a distant wing is one triangle).
void quad(std::vector<MeshVertex>& out, vec3 a, vec3 b, vec3 c, vec3 d, float part) {
  triangle(out, a, b, c, part);
  triangle(out, a, c, d, part, true);
}

}  // namespace

std::vector<MeshVertex> bird_mesh() {
  std::vector<MeshVertex> v;
  // Body: head at +x, tail end at -x, half-height and half-width 0.5 (scaled by b).
  const vec3 head(0.5f, 0.05f, 0), tail(-0.5f, 0, 0), top(0.1f, 0.5f, 0), bottom(0.1f, -0.5f, 0),
      right(0.1f, 0, 0.5f), left(0.1f, 0, -0.5f);
  for (const auto& [a, b] : std::array<std::pair<vec3, vec3>, 4>{
           {{top, right}, {right, bottom}, {bottom, left}, {left, top}}}) {
    triangle(v, head, a, b, 0.0f, true);
    triangle(v, tail, b, a, 0.0f, true);
  }
  for (float side : {0.0f, 4.0f}) {
    // Arm: a rectangle. Hand: tapering to a point at the tip, swept back.
    quad(v, {-0.5f, 0, 0}, {0.5f, 0, 0}, {0.5f, 0, 1}, {-0.5f, 0, 1}, 1.0f + side);
    quad(v, {-0.5f, 0, 0}, {0.5f, 0, 0}, {0.25f, 0, 1}, {-0.6f, 0, 0.9f}, 2.0f + side);
  }
  // Tail: a fan of four slices, radius fraction 0..1, angle fraction -0.5..0.5.
  for (int i = 0; i < 4; ++i)
    triangle(v, {0, 0, 0}, {1, 0, -0.5f + 0.25f * i}, {1, 0, -0.25f + 0.25f * i}, 3.0f, true);
  return v;
}

std::vector<MeshVertex> distant_bird_mesh() {
  std::vector<MeshVertex> out;
  for (const MeshVertex& v : bird_mesh())
    if (v.normal.w == 0.0f) out.push_back(v);
  return out;
}

std::vector<MeshVertex> sphere_mesh() {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  const std::array<vec3, 12> p = {vec3(-1, t, 0), vec3(1, t, 0), vec3(-1, -t, 0), vec3(1, -t, 0),
                                  vec3(0, -1, t), vec3(0, 1, t), vec3(0, -1, -t), vec3(0, 1, -t),
                                  vec3(t, 0, -1), vec3(t, 0, 1), vec3(-t, 0, -1), vec3(-t, 0, 1)};
  const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                            {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                            {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                            {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  std::vector<MeshVertex> v;
  for (const auto& f : faces) {
    const vec3 a = glm::normalize(p[f[0]]), b = glm::normalize(p[f[1]]), c = glm::normalize(p[f[2]]);
    const vec3 ab = glm::normalize(a + b), bc = glm::normalize(b + c), ca = glm::normalize(c + a);
    triangle(v, a, ab, ca, 0.0f);
    triangle(v, ab, b, bc, 0.0f);
    triangle(v, ca, bc, c, 0.0f);
    triangle(v, ab, bc, ca, 0.0f);
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
