// The table of Species fields a scenario file may set: name, member and the unit in the file.
#pragma once

#include <span>
#include <string_view>

#include "model/species.h"

namespace aeroflock::io {

enum class FileUnit {
  plain,               // as in the struct (cm, g, s, Hz, dyn, fractions)
  degrees,             // degrees in the file, radians in the struct
  degrees_per_second,  // deg/s in the file, rad/s in the struct
};

struct SpeciesField {
  std::string_view name;  // the C++ member name, also the TOML key
  double Species::*member;
  FileUnit unit;
};

// Every numeric field of Species, in declaration order. A field added to Species must be added
// here too: test_scenario_file checks that the table covers the whole struct.
std::span<const SpeciesField> species_fields();

// A value as written in the file, converted to the struct's unit.
double from_file_unit(double value, FileUnit unit);

}  // namespace aeroflock::io
