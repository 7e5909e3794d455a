#version 450
// Target spheres and branches: a unit mesh per instance, placed and scaled from the world's
// buffers (targets: centre and radius; branches: point and direction), from the eye.
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"
#define BIRDS_ACCESS readonly
#include "buffers.glsl"

// The mesh, read by vertex index (engine/render/meshes.h).
layout(std430, set = 0, binding = kBindingMesh) readonly buffer Mesh { MeshVertex mesh[]; };
layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_world;
layout(location = 2) flat out uint out_kind;

layout(constant_id = 0) const uint kKind = 0u;  // 0 target spheres, 1 branches, 2 route lines
// Route lines: pairs of target indices (kind 2 reads these instead of a mesh).
layout(std430, set = 0, binding = kBindingSegments) readonly buffer Segments { uvec2 segments[]; };

void main() {
  uint vertex = kKind == 2u ? 0u : uint(gl_VertexIndex);
  vec3 in_position = mesh[vertex].position.xyz, in_normal = mesh[vertex].normal.xyz;
  vec3 world, normal = in_normal;
  if (kKind == 0u) {
    GpuTarget t = targets[gl_InstanceIndex];
    world = t.centre_radius.xyz + tile_shift(t.tile_x, t.tile_z, frame.tile_x, frame.tile_z) - frame.eye.xyz + t.centre_radius.w * in_position;
  } else if (kKind == 2u) {
    uvec2 ends = segments[gl_InstanceIndex];
    GpuTarget t = targets[gl_VertexIndex == 0 ? ends.x : ends.y];
    world = t.centre_radius.xyz + tile_shift(t.tile_x, t.tile_z, frame.tile_x, frame.tile_z) - frame.eye.xyz;
    normal = vec3(0.0, 1.0, 0.0);
  } else {
    GpuBranch br = branches[gl_InstanceIndex];
    vec3 along = normalize(br.direction.xyz), up = vec3(0, 1, 0), across = cross(along, up);
    mat3 m = mat3(along, up, across);
    // A branch 1 m long and 4 cm thick, its top at the perch point.
    world = br.point.xyz + tile_shift(br.tile_x, br.tile_z, frame.tile_x, frame.tile_z) - frame.eye.xyz +
            m * (in_position * vec3(100.0, 4.0, 4.0) - vec3(0.0, 4.0, 0.0));
    normal = m * in_normal;
  }
  out_normal = normal;
  out_world = world;
  out_kind = kKind;
  gl_Position = frame.view_projection * vec4(world, 1.0);
}
