// The low-polygon meshes the renderer draws, read by the vertex shaders from storage buffers
// (vertex pulling): a bird in parts, near and far, and a box for branches and their posts.
#pragma once

#include <vector>

#include "gpu/host_device.h"

namespace aeroflock::render {

using gpu::MeshVertex;

// What colours a bird's vertex (MeshVertex::normal.w), besides its species' plumage.
enum class Tint { plumage = 0, beak = 1, flight_feathers = 2 };

// Parts (MeshVertex::position.w): 0 body and head (a smooth lathe along x, -0.5 tail to +0.5
// crown, scaled to a x b x b, with a beak), 1 and 2 the right arm and hand (span 0..1 along z,
// chord -0.5..0.5 along x, leading edge +x; secondaries and slotted primaries), 3 the tail's fan
// (x: radius fraction, z: angle fraction of the opening), 5 and 6 the left arm and hand, 7 the
// legs (placed with the body; y from the hip, 0, to the foot, 1: bird.vert).
std::vector<MeshVertex> bird_mesh();
// The same bird from afar, in four triangles, one a wing segment: a few pixels wide, its wings
// are what shows (and every vertex counts when a flock of 100,000 is drawn).
std::vector<MeshVertex> distant_bird_mesh();
// The same bird a few pixels wide, in a window (View::tiny_pixels): one triangle a wing, from the
// arm's root chord to the hand's tip, without the bend at the wrist. Drawing a vertex costs a CPU
// device (lavapipe) most of a window's frame with a large flock in view.
std::vector<MeshVertex> tiny_bird_mesh();
// A box from -0.5 to 0.5 in x, 0 to 1 in y, -0.5 to 0.5 in z.
std::vector<MeshVertex> box_mesh();

}  // namespace aeroflock::render
