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

enum class Range { any, positive, non_negative };

// One TOML table. The constructor rejects keys not in `keys` (naming the valid ones). Getters
// return the fallback when a key is absent and throw ScenarioError when it is present but of the
// wrong type or out of range. `keys` must outlive the reader.
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

  double number(std::string_view key, double fallback, Range range = Range::any) const;
  int64_t integer(std::string_view key, int64_t fallback, int64_t min,
                  int64_t max = std::numeric_limits<int64_t>::max()) const;
  bool boolean(std::string_view key, bool fallback) const;
  std::string string(std::string_view key, std::string fallback) const;
  std::optional<LocatedString> located_string(std::string_view key) const;
  std::vector<LocatedString> strings(std::string_view key) const;
  glm::dvec3 vec3(std::string_view key, glm::dvec3 fallback, Range range = Range::any) const;

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

// The index of the item named `ref.value` in `items` (anything with a `name`), or a located
// "unknown WHAT" error listing the known names.
template <class T>
uint32_t index_by_name(const std::vector<T>& items, const LocatedString& ref,
                       std::string_view what) {
  std::string known;
  for (size_t i = 0; i < items.size(); ++i) {
    if (items[i].name == ref.value) return static_cast<uint32_t>(i);
    known += (i ? ", " : "") + items[i].name;
  }
  fail(ref.where, "unknown " + std::string(what) + " \"" + ref.value + "\"" +
                      (known.empty() ? " (none defined)" : " (known: " + known + ")"));
}

// Fails when `items` already holds an item named `name.value`.
template <class T>
void check_unique(const std::vector<T>& items, const LocatedString& name, std::string_view what) {
  for (const T& item : items)
    if (item.name == name.value)
      fail(name.where, "duplicate " + std::string(what) + " name \"" + name.value + "\"");
}

}  // namespace aeroflock::io
