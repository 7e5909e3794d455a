// Where the flock is seen from.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace aeroflock::render {

// eye and target are from `origin` (world), so that a camera 1,000 km out keeps small floats.
struct Camera {
  glm::dvec3 origin{0.0};                  // world, cm
  glm::vec3 eye{0.0f, 3000.0f, -6000.0f};  // cm from origin
  glm::vec3 target{0.0f, 3000.0f, 0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fov_y = 0.87f;       // rad (50 degrees)
  float near_plane = 20.0f;  // cm
  float far_plane = 2.0e6f;  // cm
  // World to Vulkan clip space (y down, depth 0..1) for an image of width / height `aspect`.
  glm::mat4 view_projection(float aspect) const;
  glm::dvec3 eye_world() const { return origin + glm::dvec3(eye); }
  glm::dvec3 target_world() const { return origin + glm::dvec3(target); }
  // The same camera with eye and target from `new_origin`.
  Camera from(const glm::dvec3& new_origin) const;
};

}  // namespace aeroflock::render
