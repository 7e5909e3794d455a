#include "io/species_fields.h"

namespace aeroflock::io {
namespace {

constexpr SpeciesField kFields[] = {
#define AF_SPECIES_PARAM(param, default_value, unit, rule, max) \
  {#param, &Species::param, Unit::unit},
#include "model/species.def"
#undef AF_SPECIES_PARAM
};

}  // namespace

std::span<const SpeciesField> species_fields() { return kFields; }

}  // namespace aeroflock::io
