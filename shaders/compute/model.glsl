// The bird model of engine/model, file for file and function for function, in float. Force and
// integration statements are `precise` so that they are not contracted into FMAs: the CPU
// reference is built with -ffp-contract=off, and the two then differ only by float-vs-double
// rounding. The includer declares the buffers (buffers.glsl) and the push constants `pc`
// (StepConstants). Each part uses only those before it.

// What the scenario can reach (host_device.h: kConstantWakes...; gpu/layout.h: model_constants).
// The defaults reach everything: a pipeline that sets none carries all the code.
layout(constant_id = kConstantWakes) const bool kWakes = true;
layout(constant_id = kConstantBranches) const bool kBranches = true;
layout(constant_id = kConstantWindProfile) const uint kWindProfile = kWindProfileAny;

#include "bird.glsl"          // trigonometry, rotation, wing angles, tail opening (with drawing)
#include "world.glsl"         // world.cpp
#include "body.glsl"          // body.cpp
#include "wingbeat.glsl"      // wingbeat.cpp
#include "aerodynamics.glsl"  // aerodynamics.cpp
#include "wake.glsl"          // wake.cpp
#include "tail.glsl"          // tail.cpp
#include "control.glsl"       // control.cpp
#include "route.glsl"         // route.cpp
#include "bird_step.glsl"     // step.cpp
