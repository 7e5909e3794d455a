// The Species fields a scenario file may set: the key, the member and the unit in the file, one
// row per line of engine/model/species.def.
#pragma once

#include <span>
#include <string_view>

#include "model/species.h"

namespace aeroflock::io {

struct SpeciesField {
  std::string_view name;  // the C++ member name, also the TOML key
  double Species::*member;
  Unit unit;  // in the file; the struct holds radians for angles
};

// Every numeric field of Species, in species.def's order.
std::span<const SpeciesField> species_fields();

}  // namespace aeroflock::io
