#pragma once
// The SPIR-V of shaders/compute/*.comp, compiled at build time (cmake/shaders.cmake).
#include <cstdint>
#include <span>
#include <string_view>

namespace aeroflock::gpu {

// The words of the shader whose file stem is `name` (e.g. "step"); std::invalid_argument if no
// such shader was built.
std::span<const uint32_t> shader_spirv(std::string_view name);

}  // namespace aeroflock::gpu
