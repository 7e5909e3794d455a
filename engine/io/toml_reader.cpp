#include "io/toml_reader.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "io/scenario_file.h"
#include "io/words.h"

namespace aeroflock::io {
namespace {

std::string join(std::span<const std::string_view> names) {
  std::string out;
  for (std::string_view name : names) out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

template <class Number>
std::string number_text(Number v) {
  char text[32];
  return std::string(text, std::to_chars(text, text + sizeof text, v).ptr);
}

// "a positive number", "a number from 1e-05 to 0.01", "0 or a number from 0.1 to 1e+06".
std::string range_phrase(const Range& range) {
  std::string phrase =
      range.min == 0 && range.above_min ? "a positive number"
      : range.min == 0                  ? "a number >= 0"
      : range.min == -range.max
          ? "a number from " + number_text(-range.max) + " to " + number_text(range.max)
          : "a number from " + number_text(range.min) + " to " + number_text(range.max);
  return range.or_zero ? "0 or " + phrase : phrase;
}

// The node as a number a scenario may give for `range`; otherwise what was expected.
struct Checked {
  double value = 0.0;
  std::string expected;  // empty: `value` holds
};
Checked check_number(const toml::node& node, const Range& range) {
  if (!node.is_number()) return {0.0, range_phrase(range)};
  const double v = node.is_integer() ? static_cast<double>(node.as_integer()->get())
                                     : node.as_floating_point()->get();
  if (!std::isfinite(v)) return {v, "a finite number"};
  if (range.or_zero && v == 0) return {v, ""};
  if (v > range.max)
    return {v, range.why.empty()
                   ? (range.or_zero ? "0 or " : "") + std::string("a number from ") +
                         number_text(range.min) + " to " + number_text(range.max)
                   : "at most " + number_text(range.max) + " (" + std::string(range.why) + ")"};
  if (v < range.min || (range.above_min && v == range.min)) return {v, range_phrase(range)};
  // Within the range: the device computes in float, where below FLT_MIN a number is subnormal
  // (flushed to 0, or its digits lost), so a direction or a parameter that is not 0 would be.
  const bool zero_allowed =
      range.or_zero || (range.min < 0 || (range.min == 0 && !range.above_min));
  if (v != 0 && std::fabs(v) < std::numeric_limits<float>::min())
    return {v, (zero_allowed ? "0 or a number at least " : "a number at least ") +
                   number_text(std::numeric_limits<float>::min()) +
                   " in size (a smaller one is subnormal in the device's float)"};
  return {v, ""};
}

}  // namespace

void fail(const Where& where, std::string_view what) {
  std::ostringstream msg;
  msg << where.file;
  if (where.region.begin.line > 0)
    msg << ':' << where.region.begin.line << ':' << where.region.begin.column;
  msg << ": error: ";
  if (!where.key.empty()) msg << where.key << ": ";
  msg << what;
  throw ScenarioError(msg.str());
}

std::string describe(const toml::node& node) {
  if (const auto* s = node.as_string()) return "\"" + s->get() + "\"";
  if (const auto* f = node.as_floating_point()) {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, f->get()).ptr;
    return std::string(text, end);
  }
  if (const auto* a = node.as_array()) return "an array of " + std::to_string(a->size());
  if (node.is_table()) return "a table";
  std::ostringstream out;
  node.visit([&](const auto& v) {
    if constexpr (!toml::is_container<decltype(v)>) out << v;
  });
  return out.str();
}

TableReader::TableReader(std::string_view file, const toml::table& table, std::string path,
                         std::span<const std::string_view> keys)
    : file_(file), table_(&table), path_(std::move(path)), keys_(keys) {
  for (const auto& [key, value] : table) {
    bool known = false;
    for (std::string_view k : keys_) known = known || k == key.str();
    if (!known)
      io::fail({file_, key.source(), key_path(key.str())},
               "unknown key" + did_you_mean(key.str(), keys_) + "; valid keys: " + join(keys_));
  }
}

std::string_view TableReader::checked_key(std::string_view key) const {
  for (std::string_view k : keys_)
    if (k == key) return key;
  throw std::logic_error("TableReader: key '" + std::string(key) + "' not declared for '" + path_ +
                         "'");
}

std::string TableReader::key_path(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

const toml::node* TableReader::find(std::string_view key) const {
  return table_->get(checked_key(key));
}

Where TableReader::where() const { return {file_, table_->source(), path_}; }

Where TableReader::where(std::string_view key) const {
  const toml::node* node = find(key);
  return {file_, node ? node->source() : table_->source(), key_path(key)};
}

void TableReader::fail(std::string_view key, std::string_view what) const {
  io::fail(where(key), what);
}

void TableReader::require(std::string_view key) const {
  if (!find(key)) fail(key, "missing required key");
}

double TableReader::number(std::string_view key, double fallback, Range range) const {
  const toml::node* node = find(key);
  if (!node) return fallback;
  const Checked c = check_number(*node, range);
  if (!c.expected.empty()) fail(key, "expected " + c.expected + ", got " + describe(*node));
  return c.value;
}

int64_t TableReader::integer(std::string_view key, int64_t fallback, int64_t min,
                             int64_t max) const {
  const toml::node* node = find(key);
  if (!node) return fallback;
  const auto v = node->value_exact<int64_t>();
  if (v && *v >= min && *v <= max) return *v;
  std::string expected = min == 1   ? "a positive integer"
                         : min == 0 ? "a non-negative integer"
                                    : "an integer >= " + std::to_string(min);
  if (v && *v > max) expected = "an integer <= " + std::to_string(max);
  fail(key, "expected " + expected + ", got " + describe(*node));
}

bool TableReader::boolean(std::string_view key, bool fallback) const {
  const toml::node* node = find(key);
  if (!node) return fallback;
  if (!node->is_boolean()) fail(key, "expected true or false, got " + describe(*node));
  return node->as_boolean()->get();
}

std::string TableReader::string(std::string_view key, std::string fallback) const {
  auto s = located_string(key);
  return s ? s->value : fallback;
}

std::optional<LocatedString> TableReader::located_string(std::string_view key) const {
  const toml::node* node = find(key);
  if (!node) return std::nullopt;
  if (!node->is_string()) fail(key, "expected a string, got " + describe(*node));
  return LocatedString{node->as_string()->get(), where(key)};
}

std::vector<LocatedString> TableReader::strings(std::string_view key) const {
  const toml::node* node = find(key);
  if (!node) return {};
  if (!node->is_array()) fail(key, "expected an array of strings, got " + describe(*node));
  std::vector<LocatedString> out;
  const toml::array& array = *node->as_array();
  for (size_t i = 0; i < array.size(); ++i) {
    Where at{file_, array[i].source(), key_path(key) + "[" + std::to_string(i) + "]"};
    if (!array[i].is_string()) io::fail(at, "expected a string, got " + describe(array[i]));
    out.push_back({array[i].as_string()->get(), at});
  }
  return out;
}

glm::dvec3 TableReader::vec3(std::string_view key, glm::dvec3 fallback, Range range) const {
  const toml::node* node = find(key);
  if (!node) return fallback;
  const toml::array* array = node->as_array();
  if (!array || array->size() != 3)
    fail(key, "expected an array of 3 numbers, got " + describe(*node));
  glm::dvec3 out;
  for (int i = 0; i < 3; ++i) {
    const Checked c = check_number((*array)[i], range);
    if (!c.expected.empty())
      io::fail({file_, (*array)[i].source(), key_path(key) + "[" + std::to_string(i) + "]"},
               "expected " + c.expected + ", got " + describe((*array)[i]));
    out[i] = c.value;
  }
  return out;
}

std::optional<TableReader> TableReader::table(std::string_view key,
                                              std::span<const std::string_view> keys) const {
  const toml::node* node = find(key);
  if (!node) return std::nullopt;
  if (!node->is_table())
    fail(key, "expected a table [" + std::string(key) + "], got " + describe(*node));
  return TableReader(file_, *node->as_table(), key_path(key), keys);
}

std::vector<TableReader> TableReader::tables(std::string_view key,
                                             std::span<const std::string_view> keys) const {
  const toml::node* node = find(key);
  if (!node) return {};
  const std::string expected = "expected an array of tables [[" + std::string(key) + "]], got ";
  if (!node->is_array()) fail(key, expected + describe(*node));
  std::vector<TableReader> out;
  const toml::array& array = *node->as_array();
  for (size_t i = 0; i < array.size(); ++i) {
    const std::string path = key_path(key) + "[" + std::to_string(i) + "]";
    if (!array[i].is_table())
      io::fail({file_, array[i].source(), path}, expected + describe(array[i]));
    out.emplace_back(file_, *array[i].as_table(), path, keys);
  }
  return out;
}

void Names::add(const LocatedString& name) {
  if (index_.contains(name.value))
    fail(name.where, "duplicate " + what_ + " name \"" + name.value + "\"");
  add(name.value);
}

void Names::add(const std::string& name) {
  const auto [at, added] = index_.emplace(name, static_cast<uint32_t>(order_.size()));
  if (added) order_.push_back(&at->first);
}

uint32_t Names::index(const LocatedString& ref) const {
  if (const auto at = index_.find(ref.value); at != index_.end()) return at->second;
  // The known names, the first few of many: a file of 10^5 targets gives a line, not a megabyte.
  constexpr size_t kListed = 20;
  std::string known;
  for (size_t i = 0; i < order_.size() && i < kListed; ++i) known += (i ? ", " : "") + *order_[i];
  if (order_.size() > kListed) known += " and " + std::to_string(order_.size() - kListed) + " more";
  fail(ref.where, "unknown " + what_ + " \"" + ref.value + "\"" +
                      (known.empty() ? " (none defined)" : " (known: " + known + ")"));
}

}  // namespace aeroflock::io
