#version 450
// A frame of the flock, then each bird's forces of its next step (step.glsl).
#extension GL_GOOGLE_include_directive : require
#define RECORD_FORCES
#include "step.glsl"
