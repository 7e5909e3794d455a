#version 450
// The neighbour grid's prefix sum within blocks (grid_scan.glsl).
#extension GL_GOOGLE_include_directive : require
#include "grid_scan.glsl"
