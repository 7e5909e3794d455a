#version 450
// A frame of the flock (step.glsl).
#extension GL_GOOGLE_include_directive : require
#include "step.glsl"
