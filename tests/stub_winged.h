// A starling with stubs for wings and no leg push, which cannot fly and hops no farther than its
// take-off throws it: its species, a target 1 km off and a route there, as scenario-file text for
// the tests that bring a bird down on the ground (test_behaviours, test_gpu_crosscheck). The
// caller adds [simulation] and its [[flocks]].
#pragma once

namespace aeroflock::testing {

inline constexpr const char* kStubWingedWorld = R"(
[[species]]
name = "stub-winged"
base = "starling"
wing_area = 10.0
leg_force = 0.0
[[targets]]
name = "t"
centre = [0.0, 3000.0, 100000.0]
[[routes]]
name = "r"
targets = ["t"]
)";

}  // namespace aeroflock::testing
