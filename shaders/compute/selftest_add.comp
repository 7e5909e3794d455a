#version 450
// Self-test of the Vulkan infrastructure (tests/test_gpu_device.cpp): sum[i] = a[i] + b[i].
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly buffer A { float a[]; };
layout(std430, set = 0, binding = 1) readonly buffer B { float b[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Sum { float sum[]; };
layout(push_constant) uniform Push { uint n; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < n) sum[i] = a[i] + b[i];
}
