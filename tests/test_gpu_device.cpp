// engine/gpu: devices, buffers, pipelines and submission on the self-test shader
// (shaders/compute/selftest_add.comp), with the Khronos validation layer on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/compute.h"
#include "gpu/device.h"
#include "gpu/host_device.h"
#include "gpu/shaders.h"

namespace gpu = aeroflock::gpu;

namespace {

// Skips the test where the machine has no Vulkan driver or device at all.
#define SKIP_WITHOUT_VULKAN()                                                                      \
  do {                                                                                             \
    try {                                                                                          \
      if (gpu::Device::list_devices().empty()) GTEST_SKIP() << "no Vulkan device on this machine"; \
    } catch (const gpu::Error& e) {                                                                \
      GTEST_SKIP() << "no Vulkan on this machine: " << e.what();                                   \
    }                                                                                              \
  } while (0)

template <class T>
std::span<const std::byte> bytes(const std::vector<T>& v) {
  return std::as_bytes(std::span(v));
}

template <class T>
std::vector<T> as(const std::vector<std::byte>& raw) {
  std::vector<T> v(raw.size() / sizeof(T));
  std::memcpy(v.data(), raw.data(), v.size() * sizeof(T));
  return v;
}

}  // namespace

TEST(GpuDevice, ListsDevices) {
  SKIP_WITHOUT_VULKAN();
  const auto devices = gpu::Device::list_devices();
  ASSERT_GE(devices.size(), 1u);
  for (const auto& d : devices) {
    std::printf(
        "%s\n  maxStorageBufferRange %llu, largest device-local heap %llu, "
        "maxMemoryAllocationSize %llu, subgroup %u\n",
        gpu::describe(d).c_str(), (unsigned long long)d.max_storage_buffer_range,
        (unsigned long long)d.device_local_heap, (unsigned long long)d.max_allocation_size,
        d.subgroup_size);
    EXPECT_FALSE(d.name.empty());
    EXPECT_GT(d.max_storage_buffer_range, 0u);
    EXPECT_GT(d.device_local_heap, 0u);
  }
}

TEST(GpuDevice, OpensWithValidation) {
  SKIP_WITHOUT_VULKAN();
  gpu::Device device(gpu::headless(-1, true));
  EXPECT_TRUE(device.validation());
  EXPECT_FALSE(device.name().empty());
  EXPECT_FALSE(device.driver().empty());
  const VkPhysicalDeviceLimits& l = device.limits();
  std::printf(
      "%s (%s): maxComputeWorkGroupSize %u %u %u, maxComputeWorkGroupInvocations %u, "
      "maxComputeWorkGroupCount[0] %u, maxPushConstantsSize %u\n",
      device.name().c_str(), device.driver().c_str(), l.maxComputeWorkGroupSize[0],
      l.maxComputeWorkGroupSize[1], l.maxComputeWorkGroupSize[2], l.maxComputeWorkGroupInvocations,
      l.maxComputeWorkGroupCount[0], l.maxPushConstantsSize);
  EXPECT_EQ(device.validation_errors(), 0);
}

TEST(GpuDevice, EmbedsShaders) {
  const auto words = gpu::shader_spirv("selftest_add");
  ASSERT_GT(words.size(), 5u);
  EXPECT_EQ(words[0], 0x07230203u);  // the SPIR-V magic number
  EXPECT_THROW(gpu::shader_spirv("no_such_shader"), std::invalid_argument);
}

TEST(GpuDevice, AddsMillionFloats) {
  SKIP_WITHOUT_VULKAN();
  gpu::Device device(gpu::headless(-1, true));
  const uint32_t n = 1'000'000;
  std::vector<float> a(n), b(n);
  for (uint32_t i = 0; i < n; ++i) {
    a[i] = 0.5f * static_cast<float>(i);
    b[i] = 1.0f / static_cast<float>(i + 1);
  }
  const VkDeviceSize size = n * sizeof(float);
  gpu::Buffer da(device, size, gpu::Memory::device_local);
  gpu::Buffer db(device, size, gpu::Memory::device_local);
  gpu::Buffer sum(device, size, gpu::Memory::device_local);
  da.upload(bytes(a));
  db.upload(bytes(b));

  gpu::ComputePipeline add(device, gpu::shader_spirv("selftest_add"), {0, 1, 2}, sizeof(uint32_t));
  add.set_buffers({{0, &da}, {1, &db}, {2, &sum}});
  {
    // Synchronous: record, submit, wait.
    gpu::Submitter submitter(device);
    submitter.run(
        [&](VkCommandBuffer cmd) { add.dispatch(cmd, gpu::group_count(n, 64), &n, sizeof n); });
    const auto got = as<float>(sum.download());
    ASSERT_EQ(got.size(), n);
    uint32_t wrong = 0;
    for (uint32_t i = 0; i < n; ++i) wrong += got[i] != a[i] + b[i];
    EXPECT_EQ(wrong, 0u);
  }
  {
    // Double-buffered frames: frame k sums the first n - k elements into `sum` and reads
    // `sum` back into readback[frame]; the host reads a frame after waiting for its fence.
    std::vector<gpu::Buffer> readback;
    for (int i = 0; i < 2; ++i) readback.emplace_back(device, size, gpu::Memory::host);
    gpu::Submitter submitter(device, 2);
    auto check_frame = [&](uint32_t k, const gpu::Buffer& out) {
      const float* got = reinterpret_cast<const float*>(out.mapped());
      const uint32_t count = n - k;
      uint32_t wrong = 0;
      for (uint32_t i = 0; i < count; i += 997) wrong += got[i] != a[i] + b[i];
      wrong += got[count - 1] != a[count - 1] + b[count - 1];
      EXPECT_EQ(wrong, 0u) << "frame " << k;
    };
    VkFence fences[2] = {};
    uint32_t frame_of_slot[2] = {};
    for (uint32_t k = 0; k < 6; ++k) {
      VkCommandBuffer cmd = submitter.begin();  // waits for this slot's previous frame
      const uint32_t slot = submitter.frame();
      if (fences[slot]) check_frame(frame_of_slot[slot], readback[slot]);
      std::memset(readback[slot].mapped(), 0, size);
      gpu::barrier_to_compute(cmd);  // after the previous frame's dispatch and copy
      const uint32_t count = n - k;
      add.dispatch(cmd, gpu::group_count(count, 64), &count, sizeof count);
      gpu::record_readback(cmd, sum, readback[slot]);
      fences[slot] = submitter.submit();
      frame_of_slot[slot] = k;
    }
    for (uint32_t slot = 0; slot < 2; ++slot) {
      submitter.wait(fences[slot]);
      check_frame(frame_of_slot[slot], readback[slot]);
    }
  }
  EXPECT_EQ(device.validation_errors(), 0);
  EXPECT_EQ(device.validation_warnings(), 0);
}

TEST(GpuDevice, ChecksStorageSize) {
  SKIP_WITHOUT_VULKAN();
  gpu::Device device;
  const size_t bird = 128;
  const gpu::DeviceInfo& info = device.info();
  VkDeviceSize limit = info.max_storage_buffer_range;
  if (info.max_allocation_size > 0) limit = std::min(limit, info.max_allocation_size);
  limit = std::min(limit, info.device_local_heap);
  const VkDeviceSize fits = limit / bird;

  EXPECT_NO_THROW(gpu::check_storage_size(device, 1000 * bird, bird));
  EXPECT_NO_THROW(gpu::check_storage_size(device, fits * bird, bird));
  try {
    gpu::check_storage_size(device, (fits + 1) * bird, bird);
    FAIL() << "no error for " << fits + 1 << " birds";
  } catch (const gpu::Error& e) {
    const std::string m = e.what();
    std::printf("%s\n", m.c_str());
    EXPECT_NE(m.find(std::to_string(fits + 1) + " birds need"), std::string::npos) << m;
    EXPECT_NE(m.find("allows " + std::to_string(limit)), std::string::npos) << m;
    EXPECT_NE(m.find("at most " + std::to_string(fits) + " birds"), std::string::npos) << m;
    if (limit == info.max_storage_buffer_range) {
      EXPECT_NE(m.find("maxStorageBufferRange"), std::string::npos) << m;
    }
  }
}

// Issue 16: a flock is checked against the work groups one dispatch may have, as against the
// storage: the error names the limit and the largest flock.
TEST(GpuDevice, ChecksGroupCount) {
  SKIP_WITHOUT_VULKAN();
  gpu::Device device;
  const uint64_t most = uint64_t(device.limits().maxComputeWorkGroupCount[0]) * gpu::kWorkgroupSize;
  EXPECT_NO_THROW(gpu::check_group_count(device, most, gpu::kWorkgroupSize));
  try {
    gpu::check_group_count(device, most + 1, gpu::kWorkgroupSize);
    FAIL() << "no error for " << most + 1 << " birds";
  } catch (const gpu::Error& e) {
    const std::string m = e.what();
    std::printf("%s\n", m.c_str());
    EXPECT_NE(m.find(std::to_string(most + 1) + " birds need"), std::string::npos) << m;
    EXPECT_NE(m.find("(maxComputeWorkGroupCount[0]): at most " + std::to_string(most) + " birds"),
              std::string::npos)
        << m;
  }
  EXPECT_EQ(gpu::storage_capacity(device, 1000), [&] {
    const gpu::DeviceInfo& info = device.info();
    VkDeviceSize limit = std::min(info.max_storage_buffer_range, info.device_local_heap);
    if (info.max_allocation_size > 0) limit = std::min(limit, info.max_allocation_size);
    return limit / 1000;
  }());
}

TEST(GpuDevice, BadIndexListsDevices) {
  SKIP_WITHOUT_VULKAN();
  const auto devices = gpu::Device::list_devices();
  try {
    gpu::Device device(gpu::headless(static_cast<int>(devices.size()) + 5, false));
    FAIL() << "no error for a bad device index";
  } catch (const gpu::Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("out of range"), std::string::npos) << m;
    for (const auto& d : devices) EXPECT_NE(m.find(d.name), std::string::npos) << m;
  }
}
