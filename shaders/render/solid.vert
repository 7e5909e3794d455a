#version 450
// Targets, routes, branches and their posts, one instance each, placed from the world's buffers,
// from the eye: a target is a ring facing the eye round its sphere (a line list), a route a line
// from target to target, a branch and its post a unit box scaled (a site on the ground a flat one).
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"
#define BIRDS_ACCESS readonly
#include "buffers.glsl"

// The mesh, read by vertex index (engine/render/meshes.h).
layout(std430, set = 0, binding = kBindingMesh) readonly buffer Mesh { MeshVertex mesh[]; };
layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_world;
layout(location = 2) flat out uint out_kind;

layout(constant_id = 0) const uint kKind =
    0u;                           // 0 target rings, 1 branches, 2 route lines, 3 posts
const uint kRingSegments = 64u;   // renderer.cpp: kRingVertices / 2
const uint kKindGroundSite = 4u;  // a branch at the ground's height, for solid.frag
// Route lines: pairs of target indices (kind 2 reads these instead of a mesh).
layout(std430, set = 0, binding = kBindingSegments) readonly buffer Segments { uvec2 segments[]; };

// The ground's height from the eye, and whether a branch at `point` (from the eye) is a site on
// the ground (where a species that does not perch lands): no post, a flat patch.
float ground_from_eye() { return frame.fog_color.w - frame.eye.y; }
bool on_ground(vec3 point) { return point.y <= ground_from_eye() + 1.0; }

void main() {
  uint vertex = kKind == 0u || kKind == 2u ? 0u : uint(gl_VertexIndex);
  vec3 in_position = mesh[vertex].position.xyz, in_normal = mesh[vertex].normal.xyz;
  vec3 world, normal = in_normal;
  uint kind = kKind;
  if (kKind == 0u) {
    GpuTarget t = targets[gl_InstanceIndex];
    vec3 centre = t.centre_radius.xyz + tile_shift(t.tile_x, t.tile_z, frame.tile_x, frame.tile_z) -
                  frame.eye.xyz;
    vec3 view = normalize(centre);
    vec3 u =
        normalize(abs(view.y) < 0.99 ? cross(view, vec3(0, 1, 0)) : cross(view, vec3(1, 0, 0)));
    vec3 v = cross(u, view);
    uint end = uint(gl_VertexIndex) / 2u + uint(gl_VertexIndex) % 2u;  // segment i: ends i, i + 1
    float a = 6.2831853 * float(end) / float(kRingSegments);
    world = centre + t.centre_radius.w * (cos(a) * u + sin(a) * v);
    normal = -view;
  } else if (kKind == 2u) {
    uvec2 ends = segments[gl_InstanceIndex];
    GpuTarget t = targets[gl_VertexIndex == 0 ? ends.x : ends.y];
    world = t.centre_radius.xyz + tile_shift(t.tile_x, t.tile_z, frame.tile_x, frame.tile_z) -
            frame.eye.xyz;
    normal = vec3(0.0, 1.0, 0.0);
  } else if (kKind == 3u) {
    // A post 10 cm thick from the ground up to the branch, 45 cm behind the perch point.
    GpuBranch br = branches[gl_InstanceIndex];
    vec3 along = normalize(vec3(br.direction.x, 0.0, br.direction.z) + vec3(1e-6, 0.0, 0.0));
    vec3 top = br.point.xyz + tile_shift(br.tile_x, br.tile_z, frame.tile_x, frame.tile_z) -
               frame.eye.xyz - 45.0 * along;
    float ground = ground_from_eye();
    // None under a site on the ground: every vertex at its foot, nothing drawn.
    vec3 size = on_ground(top) ? vec3(0.0) : vec3(10.0, top.y - ground, 10.0);
    world = vec3(top.x, ground, top.z) + in_position * size;
  } else {
    GpuBranch br = branches[gl_InstanceIndex];
    vec3 along = normalize(br.direction.xyz), up = vec3(0, 1, 0), across = cross(along, up);
    mat3 m = mat3(along, up, across);
    vec3 point =
        br.point.xyz + tile_shift(br.tile_x, br.tile_z, frame.tile_x, frame.tile_z) - frame.eye.xyz;
    // A branch 1 m long and 4 cm thick, its top at the perch point; a site on the ground (where
    // a species that does not perch lands) a patch 4 m square, 2 cm above the ground.
    bool site = on_ground(point);
    vec3 size = site ? vec3(400.0, 2.0, 400.0) : vec3(100.0, 4.0, 4.0);
    world = point + m * (in_position * size - vec3(0.0, site ? 0.0 : 4.0, 0.0));
    normal = m * in_normal;
    kind = site ? kKindGroundSite : kKind;
  }
  out_normal = normal;
  out_world = world;
  out_kind = kind;
  gl_Position = frame.view_projection * vec4(world, 1.0);
}
