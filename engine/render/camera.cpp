#include "render/camera.h"

#include <glm/gtc/matrix_transform.hpp>

namespace aeroflock::render {

glm::mat4 Camera::view_projection(float aspect) const {
  glm::mat4 projection = glm::perspectiveRH_ZO(fov_y, aspect, near_plane, far_plane);
  projection[1][1] *= -1.0f;  // Vulkan's clip space has y down
  return projection * glm::lookAtRH(eye, target, up);
}

}  // namespace aeroflock::render
