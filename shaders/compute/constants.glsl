// The step shaders' push constants (engine/gpu/layout.h: StepConstants).

layout(push_constant) uniform StepConstants {
  vec4 wind_ground;  // xyz wind, w ground height
  float dt;
  float time;        // at the start of the dispatch
  uint steps;
  uint bird_count;
  uint turning;      // 0 tail, 1 fixed-rate
  uint ground_effect;
} pc;
