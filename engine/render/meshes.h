// The low-polygon meshes the renderer draws, read by the vertex shaders from storage buffers
// (vertex pulling): a bird in parts, a sphere for targets, a box for branches.
#pragma once

#include <vector>

#include "gpu/host_device.h"

namespace aeroflock::render {

using gpu::MeshVertex;

// Body (a unit double pyramid, scaled to a x b x b), arm and hand (span 0..1 along z, chord
// -0.5..0.5 along x), tail (x: radius fraction, z: angle fraction), each wing segment twice
// (right, left).
std::vector<MeshVertex> bird_mesh();
// The same bird from afar: one triangle a wing segment, no body or tail.
std::vector<MeshVertex> distant_bird_mesh();
// A unit sphere (an icosahedron subdivided once), flat shaded.
std::vector<MeshVertex> sphere_mesh();
// A box from -0.5 to 0.5 in x, 0 to 1 in y, -0.5 to 0.5 in z.
std::vector<MeshVertex> box_mesh();

}  // namespace aeroflock::render
