// The wake's field on the compute shaders (shaders/compute/wake.glsl) against the CPU reference
// (engine/model/wake.h), point by point, with the Khronos validation layer on.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "gpu/buffer.h"
#include "gpu/compute.h"
#include "gpu/device.h"
#include "gpu/layout.h"
#include "gpu/shaders.h"
#include "gpu_test_device.h"
#include "model/constants.h"
#include "model/wake.h"

namespace aeroflock {
namespace {

using glm::dvec3;

template <class T>
std::span<const std::byte> bytes(const std::vector<T>& v) {
  return std::as_bytes(std::span(v));
}

// Sources flying every way, banked and pitched, flapping or not, and points from beside them to
// 20 spans behind, across both vortices and through their cores.
TEST(GpuWake, TheShadersFieldIsTheReferences) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  for (const Species& s : species_presets()) {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::vector<WakeSource> sources;
    std::vector<dvec3> points;
    const double b = s.box_c;
    for (int i = 0; i < 2000; ++i) {
      WakeSource w;
      w.position = dvec3{100.0 * unit(random), 2000.0 + 100.0 * unit(random), 100.0 * unit(random)};
      w.attitude = glm::angleAxis(kPi * unit(random), dvec3{0, 1, 0}) *
                   glm::angleAxis(radians(20.0) * unit(random), dvec3{0, 0, 1}) *
                   glm::angleAxis(radians(45.0) * unit(random), dvec3{1, 0, 0});
      w.air_velocity = w.attitude * dvec3{s.cruise_speed * (1.0 + 0.3 * unit(random)), 0.0, 0.0};
      w.lift = s.mass * kGravity * (1.0 + 0.5 * unit(random));
      w.phase = kPi * (1.0 + unit(random));
      w.frequency = 0.5 * (s.f_min + s.f_max);
      w.amplitude = i % 4 == 0 ? 0.0 : 0.5 * (1.0 + unit(random));
      // In the wake's frame: behind, across, up (a tenth of the points on a vortex's axis).
      const double behind = 10.0 * b * (1.0 + unit(random)) - 0.1 * b;
      const dvec3 place = vortex_place(s, w, std::max(behind, 0.0));
      const double across = i % 10 == 0 ? place.z : 0.8 * b * unit(random);
      const double up = i % 10 == 0 ? place.y : place.y + 0.3 * b * unit(random);
      points.push_back(w.position - glm::normalize(w.air_velocity) * behind +
                       w.attitude * dvec3{0.0, up, across});
      sources.push_back(w);
    }
    std::vector<gpu::GpuWakeSource> packed;
    std::vector<glm::vec4> at;
    for (size_t i = 0; i < sources.size(); ++i) {
      packed.push_back(gpu::pack(sources[i]));
      at.push_back(glm::vec4(glm::vec3(points[i]), 0.0f));
    }
    const std::vector<gpu::GpuSpecies> table{gpu::pack(s)};
    gpu::Buffer species_buffer(device, sizeof(gpu::GpuSpecies), gpu::Memory::device_local);
    gpu::Buffer source_buffer(device, packed.size() * sizeof(gpu::GpuWakeSource),
                              gpu::Memory::device_local);
    gpu::Buffer point_buffer(device, at.size() * sizeof(glm::vec4), gpu::Memory::device_local);
    gpu::Buffer velocity_buffer(device, at.size() * sizeof(glm::vec4), gpu::Memory::device_local);
    species_buffer.upload(bytes(table));
    source_buffer.upload(bytes(packed));
    point_buffer.upload(bytes(at));
    gpu::ComputePipeline probe(device, gpu::shader_spirv("wake_probe"), {0, 1, 2, 3},
                               sizeof(uint32_t));
    probe.set_buffers(
        {{0, &species_buffer}, {1, &source_buffer}, {2, &point_buffer}, {3, &velocity_buffer}});
    const uint32_t n = uint32_t(at.size());
    gpu::Submitter(device).run(
        [&](VkCommandBuffer cmd) { probe.dispatch(cmd, gpu::group_count(n, 64), &n, sizeof n); });
    const std::vector<std::byte> raw = velocity_buffer.download();
    std::vector<glm::vec4> got(n);
    std::memcpy(got.data(), raw.data(), n * sizeof(glm::vec4));
    // Float rounding: 1e-4 of the peak swirl, and on a vortex's axis, where the swirl grows by 2 /
    // core of the peak per cm, a float's rounding of places 20 m out (4 ulps, 4.8e-4 cm).
    const double tolerance = 1e-4 + 2.0 * 4.8e-4 / wake_core(s);
    double worst = 0.0, strongest = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
      const dvec3 want = wake_velocity(s, sources[i], points[i]);
      // The largest swirl there is: a vortex's at its core's edge.
      const double scale =
          wake_circulation(s, sources[i].lift, glm::length(sources[i].air_velocity)) /
          (4.0 * kPi * wake_core(s));
      const double error = glm::length(dvec3(glm::vec3(got[i])) - want) / scale;
      worst = std::max(worst, error);
      strongest = std::max(strongest, glm::length(want) / scale);
      EXPECT_LT(error, tolerance) << s.name << " case " << i;
    }
    RecordProperty(s.name + "_worst_relative_error", std::to_string(worst));
    EXPECT_GT(strongest, 0.5) << "the points reach into the cores";
  }
  EXPECT_EQ(device.validation_errors(), 0);
}

}  // namespace
}  // namespace aeroflock
