// What the host and the shaders share, written once and compiled both as C++ (engine/gpu,
// engine/render) and as GLSL (shaders/): every GPU-visible struct, binding index, push-constant
// block and the workgroup size. Buffers are std430; in C++ every vec3 and vec4 member is aligned
// to 16 bytes as std430 aligns it, so one declaration has one layout in both languages
// (tests/test_host_device.cpp compares them with the shaders' SPIR-V). Members are float, uint,
// int, uvec2 (aligned to 8, AF_V8), vec3, vec4, mat4 and arrays of vec4 or uint: a vec3 array, a
// mat3 or a float vec2 would be laid out differently by C++. All descriptors are in set 0, storage
// buffers but for the grid that perceive.comp reads as storage texel buffers (gpu/compute.h:
// Binding), and no binding number serves two buffers, compute or render.
#ifndef AEROFLOCK_HOST_DEVICE_H
#define AEROFLOCK_HOST_DEVICE_H

#ifdef __cplusplus
#include <cstdint>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace aeroflock::gpu {
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uvec2 = glm::uvec2;
using mat4 = glm::mat4;
using uint = uint32_t;
#define AF_V16 alignas(16)
#define AF_V8 alignas(8)
#define AF_UINT(name, value) inline constexpr uint32_t name = value;
#define AF_INT(name, value) inline constexpr int32_t name = value;
#else
#define AF_V16
#define AF_V8
#define AF_UINT(name, value) const uint name = value;
#define AF_INT(name, value) const int name = value;
#endif

// Invocations per workgroup of every compute shader.
AF_UINT(kWorkgroupSize, 64)

// World tiles: the device keeps a position as the whole tile it is in (x and z, ints) and its
// offset from that tile's centre (floats, within about half a tile), so that a step of 0.3 cm
// is kept to 10 micrometres anywhere within 20,000 km of the origin. Heights (y) stay
// absolute. A tile is 2^kTileLog2 cm (163.84 m); the neighbour grid's cells divide it.
AF_UINT(kTileLog2, 14)
#ifndef __cplusplus
// What a point of tile (x, z) is moved by to be seen from tile (from_x, from_z): the whole tiles
// between them, exact in float (gpu/layout.h: tiled, tile_centre).
const float kTile = float(1u << kTileLog2);
vec3 tile_shift(int x, int z, int from_x, int from_z) {
  return vec3(float(x - from_x), 0.0, float(z - from_z)) * kTile;
}
#endif

// Bindings (set 0). Compute: the flock and its world, and the forces the step records.
AF_UINT(kBindingBirds, 0)
AF_UINT(kBindingSpecies, 1)
AF_UINT(kBindingTargets, 2)
AF_UINT(kBindingRoutes, 3)
AF_UINT(kBindingRouteTargets, 4)
AF_UINT(kBindingBranches, 5)
AF_UINT(kBindingForces, 6)
// Render: each bird's pose, the detailed and distant draw lists and their indirect draws, the mesh
// drawn, the route lines.
AF_UINT(kBindingPoses, 7)
AF_UINT(kBindingDrawLists, 8)
AF_UINT(kBindingDraws, 9)
AF_UINT(kBindingMesh, 10)
AF_UINT(kBindingSegments, 11)
// Flocking (compute): each bird's perception, and the neighbour grid: a table of the occupied
// cells, open-addressed so that each cell of each flock has a slot of its own (its cell and flock,
// the bird that claimed it), a counting sort of the birds into the slots (each bird's slot and
// rank in it, the slots' counts, their starts within a scan block, the blocks' starts, each
// slot's range of sorted birds), the birds in slot order with their places in their cells, and
// the order a bird searches the cells around its own (flock.h: grid_search_order).
AF_UINT(kBindingPerception, 12)
AF_UINT(kBindingGridPlace, 13)
AF_UINT(kBindingGridCounts, 14)
AF_UINT(kBindingGridStarts, 15)
AF_UINT(kBindingGridBlocks, 16)
AF_UINT(kBindingGridPoints,
        18)  // the birds in slot order: places in their cells (xyz), indices (w, as bits)
AF_UINT(kBindingGridKeys, 19)    // each slot's cell (xyz) and flock (w; kNoFlock: an empty slot)
AF_UINT(kBindingGridOwners, 20)  // the bird that claimed each slot (kNoBird: none)
// Each slot's first and end in the sorted birds and the bounds of its birds' places in their cell
// (low, high: kBoundSteps to the cell's side, 10 bits an axis), for the search (grid_cells.comp).
AF_UINT(kBindingGridCells, 21)
AF_UINT(kBoundSteps, 1024)
AF_UINT(kBindingGridSearch,
        22)  // cell offsets (xyz) and least distances (w, parts^2), nearest first
// What the social goal reads of each bird of the grid, by bird index, two texels each
// (grid_scatter.comp; flock.glsl: social_goal): its position (xyz) and tile_x (w), its velocity
// (xyz) and tile_z (w). A tile is a whole number far inside a float's exact range; its bits did
// not do (a negative tile's are a NaN, which a device may change; WorldScale failed).
AF_UINT(kBindingGridSeen, 26)
// What a driver's limit on a shader's loops cut short, counted (two uints): the birds whose steps
// a dispatch ended short of its steps (step.glsl), and the birds whose search of the neighbour
// grid ended before it was done (flock.glsl: search); then how far the searches reached
// (perceive.comp: kReachBins counts, flock.h: SearchReach), for the host to fit the grid's cell.
AF_UINT(kBindingCutShort, 23)
// Each bird's global id (its index in the whole flock), kGhostBird set for a ghost: a copy of
// another MPI rank's bird, perceived, never stepped nor perceiving (engine/dist). On one device the
// index itself. The perception's seen_key sums ids, and ties among neighbours go by buffer index,
// which follows the ids' order.
AF_UINT(kBindingIds, 24)
AF_UINT(kGhostBird, 0x80000000u)

// The parts of its cell along each axis for which the search has an order of its own (flock.h:
// grid_search_order): a bird stops sooner the finer they are.
AF_UINT(kSearchParts, 4)

// The model's specialisation constants (model.glsl), by constant_id: what the scenario can reach,
// so that a pipeline carries only the code its birds can run (a CPU device runs both sides of a
// branch; gpu/layout.h: model_constants). A shader's own constants follow from kModelConstants.
AF_UINT(kConstantWakes, 0)        // some flock meets wakes (Flock::wake)
AF_UINT(kConstantBranches, 1)     // some route ends on a branch or landing site
AF_UINT(kConstantWindProfile, 2)  // the world's WindProfile, or kWindProfileAny: pc.wind_profile's
AF_UINT(kModelConstants, 3)
AF_UINT(kWindProfileAny, 3)

// Slots per workgroup of the grid's prefix sum (grid_scan.glsl): 16 per invocation, read as four
// uvec4, its invocations scanned in runs of 8. The grid has a whole number of such blocks.
AF_UINT(kScanBlock, 1024)
#ifdef __cplusplus
static_assert(kScanBlock % (4 * kWorkgroupSize) == 0 && kWorkgroupSize % 8 == 0);
#endif
// A bird outside the grid (it does not flock now), a slot no bird claimed, its flock.
AF_UINT(kNoBucket, 0xffffffffu)
AF_UINT(kNoBird, 0xffffffffu)
AF_INT(kNoFlock, -1)

// GpuRoute::flags
AF_UINT(kRouteLoop, 1)
AF_UINT(kRoutePathControl, 2)

#ifndef __cplusplus
// Flight modes and landing stages (engine/model/bird.h: FlightMode, LandingStage).
#define AF_FLIGHT_MODE(name, value) const uint mode_##name = value;
#define AF_LANDING_STAGE(name, value) const uint stage_##name = value;
#include "model/flight_mode.def"
#undef AF_FLIGHT_MODE
#undef AF_LANDING_STAGE
#endif

// One bird (engine/model/bird_state.def), floats for the CPU reference's doubles.
#define AF_GPU_float float
#define AF_GPU_uint uint
#define AF_GPU_uvec2 AF_V8 uvec2
#define AF_GPU_vec3 AF_V16 vec3
#define AF_GPU_vec4 AF_V16 vec4
// Its position, landing_start and via_point are offsets from the centre of tile (tile_x, tile_z).
struct GpuBird {
#define AF_BIRD_FIELD(gpu_type, cpp_type, name, initial) AF_GPU_##gpu_type name;
#include "model/bird_state.def"
#undef AF_BIRD_FIELD
  int tile_x, tile_z;
};

// A species (engine/model/species.def), then what the step derives from it, computed once on the
// host (layout.cpp, pack(const Species&)).
struct GpuSpecies {
#define AF_SPECIES_PARAM(name, default_value, unit, rule, max) float name;
#include "model/species.def"
#undef AF_SPECIES_PARAM
  float inv_inertia_x, inv_inertia_y, inv_inertia_z;  // eq. 12
  float shoulder_z, arm_length, hand_length;          // cm
  float arm_area, hand_area;                          // one wing's, cm^2
  float tail_hinge_x, tail_arm;                       // cm; tail_arm: 2/3 lr
  float tail_area_per_radian;                         // eq. 9: S_t = lr^2 / 2 phi
  float tan_bank_max;
  float open_tail;  // the tail fully open (braking), rad
};

struct GpuTarget {
  AF_V16 vec4 centre_radius;  // where it is at the frame's start (cm, from its tile), radius
  AF_V16 vec4 velocity;       // xyz, cm/s
  int tile_x, tile_z;
};

struct GpuRoute {
  uint first;  // into the route-target list
  uint count;
  uint flags;   // kRouteLoop, kRoutePathControl
  uint branch;  // branch index + 1, 0: none
};

struct GpuBranch {
  AF_V16 vec4 point;  // from its tile
  AF_V16 vec4 direction;
  int tile_x, tile_z;
};

// One bird's forces of one step (engine/model/step.h: StepForces), world frame but the torques.
struct GpuForces {
  AF_V16 vec4 wing[4];  // right arm, right hand, left arm, left hand
  AF_V16 vec4 tail;
  AF_V16 vec4 ground;
  AF_V16 vec4 legs;
  AF_V16 vec4 gravity;
  AF_V16 vec4 total;
  AF_V16 vec4 tail_torque;     // body frame
  AF_V16 vec4 torque;          // body frame
  AF_V16 vec4 wake_air_power;  // xyz the wakes' air at the wing points, mean, world; w the power
};

// A bird's wake as a neighbour sees it (engine/model/wake.h: WakeSource).
struct GpuWakeSource {
  AF_V16 vec4 position_phase;          // xyz its centre (cm), w its wingbeat phase (rad)
  AF_V16 vec4 air_velocity_frequency;  // xyz its velocity through the air (cm/s), w frequency (Hz)
  AF_V16 vec4 attitude;                // body to world, x y z w
  AF_V16 vec4 lift_amplitude;          // x lift (dyn), y amplitude, z w unused
};

// The wakes a perception keeps (model/constants.h: kWakeSources).
AF_UINT(kGpuWakeSources, 2)

// What a bird's perception leaves for its steps (engine/model/flock.h: Perception). The wakes'
// places are in the frame of the bird's world tile.
struct GpuPerception {
  AF_V16 vec3 direction;  // u(d), world; 0 when it sees no one
  float airspeed;         // commanded, cm/s
  uint neighbours;        // how many it sees
  float nearest;          // cm to the nearest of them
  uint seen_key;          // checksum of the seen birds' indices (flock.h)
  uint wakes;             // how many of wake[] it meets
  uint wake_step;         // the step they were seen at (its low 32 bits)
  int wake_tile_x;        // the world tile of the wakes' places (the bird's then)
  int wake_tile_z;
  float phase_rate;  // formation flying: its wingbeat's phase runs this much faster, rad/s
  GpuWakeSource wake[kGpuWakeSources];
};

// Push constants of step.comp, step_forces.comp and the flocking passes (grid_*.comp,
// perceive.comp).
struct StepConstants {
  AF_V16 vec4 wind_ground;  // xyz wind (cm/s), w ground height (cm)
  float dt;
  uint rest_steps;  // whole_steps(kRestAfterTouchdown, dt): the rest after a touch-down
  uint steps;       // steps this dispatch (0: step_forces.comp records the forces only)
  uint bird_count;
  uint turning;  // TurningModel: 0 tail, 1 fixed-rate
  uint ground_effect;
  uint next_targets;  // step_forces.comp: where the targets at the next frame's start begin
  uint flocking;      // 1: the birds steer by their perception
  float grid_cell;    // the neighbour grid's cell, cm
  uint buckets;       // its slots, a power of two, a whole number of kScanBlock
  uint grid_bits;  // the table's sides, 2^x by 2^y by 2^z cells: x | y << 8 | z << 16 (grid.glsl)
  uint frame;      // the frame's index (perceive.comp: whose reaction is due)
  float frame_seconds;
  uint wind_profile;    // WindProfile (engine/model/world.h): 0 uniform, 1 power law, 2 logarithmic
  float wind_height;    // where the wind is wind_ground.xyz, cm above the ground
  float wind_exponent;  // of the power law
  float wind_roughness;  // z0 of the logarithmic profile, cm
  uint targets_base;     // where this frame's targets begin (several frames a submission)
  uint first_step;       // the frame's steps before this dispatch (a long frame takes several)
  uint frame_steps;      // the frame's steps: the dispatch that ends it retiles and records forces
  // The search's order for the grid's cell (flock.h: grid_search_order): where its list for a
  // cell's first part begins in grid_search, and the cells a part's list holds.
  uint search_first;
  uint search_cells;
  AF_V8 uvec2 step;  // the run's steps before the frame's first (low word first): its clock
};

// Render: each bird's pose for drawing (pose.comp), six 3x4 transforms (body, right arm, right
// hand, tail, left arm, left hand; part-local to world, by rows), the tail's opening (x), the
// bird's species (y, as bits), its wingspan (z, cm: the size of its shadow, shadow.vert) and how
// far its feet reach under its centre (w, body heights: on its legs stand_height / box_b, or to
// the ground where that is nearer; in flight 0).
struct Pose {
  AF_V16 vec4 rows[18];
  AF_V16 vec4 tail;
};

struct DrawCommand {  // VkDrawIndirectCommand
  uint vertex_count;
  uint instance_count;
  uint first_vertex;
  uint first_instance;
};

// Push constants of pose.comp.
struct PoseConstants {
  AF_V16 vec4 eye;  // xyz the eye, from the centre of tile (tile_x, tile_z) (FrameConstants)
  uint bird_count;
  uint capacity;    // of each list
  float lod_scale;  // a bird farther than its span times this is distant
  int tile_x;
  int tile_z;
  float min_angle;   // rad: a bird is drawn at least this wide (distant birds grown to it)
  float tiny_scale;  // a bird farther than its span times this is tiny (0: none; View::tiny_pixels)
  float ground_height;  // cm: where the feet of a bird on the ground are
};

// Push constants of every render shader (frame.glsl): the camera and the light. Everything is
// drawn from the eye (view_projection has it at the origin), so that a flock 1,000 km out is drawn
// in small floats as one at the origin, and the view rays are exact; eye is where the eye is, from
// the centre of its tile (tile_x, tile_z): what is drawn is moved by -eye and the whole tiles
// between.
struct FrameConstants {
  AF_V16 mat4 view_projection;
  AF_V16 vec4 eye;        // xyz the eye (cm, from its tile's centre; y: world height), w time (s)
  AF_V16 vec4 sun;        // xyz towards the sun, w fog density (1/cm)
  AF_V16 vec4 fog_color;  // rgb, w ground height
  uint list_offset;       // where the draw's birds start in the lists (bird.vert)
  int tile_x;
  int tile_z;
  uint shadow_stride;  // every this many-th bird casts a shadow, for that many (shadow.vert)
};

// A mesh vertex (engine/render/meshes.h), read by vertex index.
struct MeshVertex {
  AF_V16 vec4 position;  // xyz, w: the bird part (0 body, 1 arm, 2 hand, 3 tail; +4 left)
  AF_V16 vec4 normal;    // xyz, w: birds: render::Tint
};

#ifdef __cplusplus
}  // namespace aeroflock::gpu
#endif
#undef AF_UINT
#undef AF_INT
#undef AF_V16
#undef AF_GPU_float
#undef AF_GPU_uint
#undef AF_GPU_vec3
#undef AF_GPU_vec4

#endif  // AEROFLOCK_HOST_DEVICE_H
