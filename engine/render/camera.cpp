#include "render/camera.h"

#include <glm/gtc/matrix_transform.hpp>

namespace aeroflock::render {

glm::mat4 Camera::view_projection(float aspect) const {
  glm::mat4 projection = glm::perspectiveRH_ZO(fov_y, aspect, near_plane, far_plane);
  projection[1][1] *= -1.0f;  // Vulkan's clip space has y down
  return projection * glm::lookAtRH(eye, target, up);
}

Camera Camera::from(const glm::dvec3& new_origin) const {
  Camera c = *this;
  c.origin = new_origin;
  c.eye = glm::vec3(eye_world() - new_origin);
  c.target = glm::vec3(target_world() - new_origin);
  return c;
}

}  // namespace aeroflock::render
