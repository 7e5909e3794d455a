#include "gpu/error.h"

namespace aeroflock::gpu {

const char* to_string(VkResult result) {
  switch (result) {
#define AEROFLOCK_CASE(r) \
  case r:                 \
    return #r;
    AEROFLOCK_CASE(VK_SUCCESS)
    AEROFLOCK_CASE(VK_NOT_READY)
    AEROFLOCK_CASE(VK_TIMEOUT)
    AEROFLOCK_CASE(VK_INCOMPLETE)
    AEROFLOCK_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    AEROFLOCK_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    AEROFLOCK_CASE(VK_ERROR_INITIALIZATION_FAILED)
    AEROFLOCK_CASE(VK_ERROR_DEVICE_LOST)
    AEROFLOCK_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    AEROFLOCK_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    AEROFLOCK_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    AEROFLOCK_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    AEROFLOCK_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    AEROFLOCK_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    AEROFLOCK_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    AEROFLOCK_CASE(VK_ERROR_UNKNOWN)
#undef AEROFLOCK_CASE
    default:
      return "VkResult (unknown code)";
  }
}

void check(VkResult result, const char* what) {
  if (result != VK_SUCCESS)
    throw Error(std::string(what) + ": " + to_string(result) + " (" +
                std::to_string(static_cast<int>(result)) + ")");
}

}  // namespace aeroflock::gpu
