#version 450
// The neighbour grid, 5 of 5: each bird in the grid writes its place in its cell and its index at
// its slot's first plus its rank: the birds in slot order, compact for the search.
#extension GL_GOOGLE_include_directive : require
#define BIRDS_ACCESS readonly
#include "buffers.glsl"
layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };
layout(std430, set = 0, binding = kBindingGridPlace) readonly buffer GridPlace {
  uvec2 grid_place[];
};
layout(std430, set = 0, binding = kBindingGridRanges) readonly buffer GridRanges {
  uvec2 grid_ranges[];
};
layout(std430, set = 0, binding = kBindingGridPoints) writeonly buffer GridPoints {
  vec4 grid_points[];
};
#include "bird.glsl"
#include "grid.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.bird_count) return;
  uvec2 place = grid_place[i];
  if (place.x == kNoBucket) return;
  uint e = grid_ranges[place.x].x + place.y;
  vec3 inside;
  grid_cell(birds[i], pc.grid_cell, inside);
  grid_points[e] = vec4(inside, uintBitsToFloat(i));
}
