// Reading one TOML table with located errors: the scenario parser's building block.
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <glm/vec3.hpp>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace aeroflock::io {

// A place in a scenario file: the file's name, a region in it and the dotted key, e.g.
// "flocks[0].count".
struct Where {
  std::string_view file;
  toml::source_region region;
  std::string key;
};

// Throws ScenarioError "FILE:LINE:COLUMN: error: KEY: WHAT" (without LINE:COLUMN when the region
// is unknown, without "KEY: " when the key is empty).
[[noreturn]] void fail(const Where& where, std::string_view what);

// A value as the file wrote it, for "got ..." in messages: -3, "fast", an array, a table.
std::string describe(const toml::node& node);

// A string value together with where it was written.
struct LocatedString {
  std::string value;
  Where where;
};

// What a number of a scenario file may be, besides finite and normal (every number is): within
// [min, max], min itself excluded when `above_min`, and 0 besides when `or_zero` (a target's
// period: 0 for none). `why` says what sets max, for the message ("the speed of sound").
struct Range {
  double min = 0.0;
  double max = 0.0;
  bool above_min = false;
  bool or_zero = false;
  std::string_view why = {};
};
constexpr Range positive(double max, std::string_view why = {}) {
  return {0.0, max, true, false, why};
}
constexpr Range non_negative(double max, std::string_view why = {}) {
  return {0.0, max, false, false, why};
}
// From -max to max.
constexpr Range magnitude(double max, std::string_view why = {}) {
  return {-max, max, false, false, why};
}
constexpr Range between(double min, double max, std::string_view why = {}) {
  return {min, max, false, false, why};
}

// One TOML table. The constructor rejects keys not in `keys` (naming the valid ones). Getters
// return the fallback when a key is absent and throw ScenarioError when it is present but of the
// wrong type or out of range. Every number must be finite and normal in the device's float (0 or
// at least FLT_MIN, 1.2e-38, in size: a smaller one is subnormal there, flushed to 0 or losing
// its digits). `keys` must outlive the reader.
class TableReader {
 public:
  TableReader(std::string_view file, const toml::table& table, std::string path,
              std::span<const std::string_view> keys);

  const toml::node* find(std::string_view key) const;
  // Where the key's value is, or where the table starts when the key is absent.
  Where where(std::string_view key) const;
  Where where() const;
  [[noreturn]] void fail(std::string_view key, std::string_view what) const;
  // Fails with "missing key" when absent.
  void require(std::string_view key) const;

  double number(std::string_view key, double fallback, Range range) const;
  int64_t integer(std::string_view key, int64_t fallback, int64_t min,
                  int64_t max = std::numeric_limits<int64_t>::max()) const;
  bool boolean(std::string_view key, bool fallback) const;
  std::string string(std::string_view key, std::string fallback) const;
  std::optional<LocatedString> located_string(std::string_view key) const;
  std::vector<LocatedString> strings(std::string_view key) const;
  // Each of the three numbers in `range`.
  glm::dvec3 vec3(std::string_view key, glm::dvec3 fallback, Range range) const;

  // [key] as a table, absent: nullopt.
  std::optional<TableReader> table(std::string_view key,
                                   std::span<const std::string_view> keys) const;
  // [[key]] as an array of tables, absent: empty.
  std::vector<TableReader> tables(std::string_view key,
                                  std::span<const std::string_view> keys) const;

  const std::string& path() const { return path_; }

 private:
  std::string key_path(std::string_view key) const;
  std::string_view checked_key(std::string_view key) const;

  std::string_view file_;
  const toml::table* table_;
  std::string path_;
  std::span<const std::string_view> keys_;
};

// The names of a scenario's items of one kind (species, targets, ...), each with its index: a
// look-up costs the same however many there are, so loading stays linear in the file's size.
class Names {
 public:
  explicit Names(std::string_view what) : what_(what) {}
  // Adds the next item's name (its index: the names added before it); a located "duplicate WHAT
  // name" error when it is already there.
  void add(const LocatedString& name);
  // A name that is not in a file (the presets), unlocated.
  void add(const std::string& name);
  // The index of the item named `ref.value`, or a located "unknown WHAT" error naming the known
  // ones (the first few of many).
  uint32_t index(const LocatedString& ref) const;
  size_t size() const { return order_.size(); }

 private:
  std::string what_;
  std::unordered_map<std::string, uint32_t> index_;
  std::vector<const std::string*> order_;  // the keys of index_, in the order added
};

}  // namespace aeroflock::io
