#pragma once
// Errors of the Vulkan backend: everything that can go wrong is a gpu::Error, never a crash.
#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace aeroflock::gpu {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// "VK_ERROR_OUT_OF_DEVICE_MEMORY", ...
const char* to_string(VkResult result);

// Throws Error("<what>: <result>") unless result is VK_SUCCESS.
void check(VkResult result, const char* what);

}  // namespace aeroflock::gpu
