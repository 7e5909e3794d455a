// A species: Table 1 of the paper plus the parameters docs/MODEL.md adds (kinematics, coefficient
// curves, control and take-off/landing constants), listed in species.def. Angles in radians,
// lengths in cm.
#pragma once

#include <numbers>
#include <string>
#include <string_view>
#include <vector>

namespace aeroflock {

// How people give a parameter (scenario files, docs); the struct holds radians for angles.
enum class Unit { plain, degrees, degrees_per_second };
constexpr double from_unit(double value, Unit unit) {
  return unit == Unit::plain ? value : value * (std::numbers::pi / 180.0);
}

// What validate() asks of one parameter on its own (species.def).
enum class Rule { positive, non_negative, fraction, within_90, bank, any };

// The parameters, defaults and rules are listed once, in species.def.
struct Species {
  std::string name;
#define AF_SPECIES_PARAM(param, default_value, unit, rule, max) \
  double param = from_unit(default_value, Unit::unit);
#include "species.def"
#undef AF_SPECIES_PARAM
};

Species eagle();              // Table 1, Fig. 16 column, plus calibrated parameters
Species starling();           // Table 1, Figs. 17-21 column, plus calibrated parameters
Species ibis();               // the northern bald ibis, a formation migrant (beyond the paper)
Species goose();              // the greylag goose, a formation migrant (beyond the paper)
Species european_starling();  // the real European starling of the field (beyond the paper)
std::vector<Species> species_presets();
// Throws std::invalid_argument naming the first bad parameter, e.g. "f_min > f_max".
void validate(const Species& s);

// Derived quantities.
struct Inertia {
  double x, y, z;  // eq. 12, g cm^2
};
Inertia box_inertia(const Species& s);

}  // namespace aeroflock
