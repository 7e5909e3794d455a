// The bird model of engine/model, file for file and function for function, in float. Force and
// integration statements are `precise` so that they are not contracted into FMAs: the CPU
// reference is built with -ffp-contract=off, and the two then differ only by float-vs-double
// rounding. The includer declares the buffers (buffers.glsl) and the push constants `pc`
// (StepConstants), and kWakes (whether any flock meets wakes: step.glsl). Each part uses only those
// before it.

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
