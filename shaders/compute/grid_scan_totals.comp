#version 450
// The neighbour grid's prefix sum of the blocks' totals (grid_scan.glsl).
#extension GL_GOOGLE_include_directive : require
#define SCAN_TOTALS
#include "grid_scan.glsl"
