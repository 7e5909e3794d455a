// The Vulkan device of a test program, validation on. A machine with no Vulkan device skips the
// tests that need one; a device that exists but fails to start (a missing validation layer, a
// broken driver) fails them.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "gpu/device.h"
#include "gpu/error.h"

namespace aeroflock::testing {

struct TestDevice {
  std::unique_ptr<gpu::Device> device;
  std::string error;  // why a device that exists did not start
};

// One device for the whole test program (graphics: it can also render).
inline const TestDevice& test_device(bool graphics = false) {
  static TestDevice d = [graphics] {
    TestDevice t;
    try {
      if (gpu::Device::list_devices().empty()) return t;
    } catch (const gpu::Error&) {
      return t;  // no Vulkan driver at all: no device
    }
    try {
      gpu::DeviceOptions options = gpu::headless(-1, true);
      options.graphics = graphics;
      t.device = std::make_unique<gpu::Device>(options);
    } catch (const std::exception& e) {
      t.error = e.what();
    }
    return t;
  }();
  return d;
}

}  // namespace aeroflock::testing

// Declares `gpu::Device& name`, or skips the test (no device) or fails it (a device that did not
// start).
#define AEROFLOCK_DEVICE_OR_SKIP(name, graphics)                            \
  const ::aeroflock::testing::TestDevice& name##_holder =                   \
      ::aeroflock::testing::test_device(graphics);                          \
  if (!name##_holder.device) {                                              \
    if (!name##_holder.error.empty())                                       \
      FAIL() << "the Vulkan device did not start: " << name##_holder.error; \
    GTEST_SKIP() << "no Vulkan device on this machine";                     \
  }                                                                         \
  ::aeroflock::gpu::Device& name = *name##_holder.device
