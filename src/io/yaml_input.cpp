#include "io/yaml_input.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include "common/error.hpp"
#include "io/yaml_guard.hpp"

namespace fibrane::io {

struct YamlNode::Document {
  std::string file;
  // Keys requested per map path. Keyed by path (not by node object) so that every copy of a node and
  // every re-lookup of the same map share one record.
  struct ReadMap {
    YAML::Node node;
    int line = 0;
    std::set<std::string> keys;
  };
  std::map<std::string, ReadMap> read_maps;
};

namespace {

int line_of(const YAML::Node& node, int fallback) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? fallback : mark.line + 1;
}

// Quoted scalars carry the non-specific tag "!"; plain ones carry "?". A quoted "1.5" is a string.
bool is_quoted(const YAML::Node& node) { return node.Tag() == "!"; }

std::optional<double> parse_double(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty() || text.front() == '+') return std::nullopt;
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<int> parse_int(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty() || text.front() == '+') return std::nullopt;
  long long value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < INT_MIN || value > INT_MAX) {
    return std::nullopt;
  }
  return static_cast<int>(value);
}

std::string quoted_list(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& name : names) out += (out.empty() ? "'" : ", '") + name + "'";
  return out;
}

// The closest known name, if it is plausibly a typo: at most a third of the name's length changed.
std::optional<std::string> closest(const std::string& word, const std::vector<std::string>& known) {
  std::optional<std::string> best;
  std::size_t best_distance = std::max<std::size_t>(1, word.size() / 3) + 1;
  for (const auto& candidate : known) {
    const std::size_t d = edit_distance(word, candidate);
    // A short word with every letter changed is no typo ('d' is not a misspelt 'b').
    if (d < best_distance && d < std::max(word.size(), candidate.size())) {
      best_distance = d;
      best = candidate;
    }
  }
  return best;
}

// yaml-cpp keeps duplicate map keys and silently returns the first; reject them up front.
void check_duplicate_keys(const YAML::Node& node, const std::string& file) {
  if (node.IsMap()) {
    std::set<std::string> seen;
    for (const auto& entry : node) {
      if (entry.first.IsScalar() && !seen.insert(entry.first.Scalar()).second) {
        throw InputError(fmt::format("{}:{}: duplicate key '{}'", file, line_of(entry.first, 0),
                                     entry.first.Scalar()));
      }
      check_duplicate_keys(entry.second, file);
    }
  } else if (node.IsSequence()) {
    for (const auto& item : node) check_duplicate_keys(item, file);
  }
}

}  // namespace

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitute = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
    }
  }
  return row[b.size()];
}

YamlNode::YamlNode(std::shared_ptr<Document> doc, YAML::Node node, std::string path, int line)
    : doc_(std::move(doc)), node_(std::move(node)), path_(std::move(path)), line_(line) {}

YamlNode YamlNode::load_string(const std::string& text, const std::string& source_name) {
  auto doc = std::make_shared<Document>();
  doc->file = source_name;
  check_yaml_text(text, source_name);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}:{}: YAML syntax error: {}", source_name, e.mark.line + 1, e.msg));
  }
  check_duplicate_keys(root, source_name);
  return YamlNode(std::move(doc), root, "", line_of(root, 1));
}

YamlNode YamlNode::load_file(const std::string& path) { return load_string(read_text_limited(path), path); }

const std::string& YamlNode::file() const { return doc_->file; }

YamlNode YamlNode::child(const YAML::Node& value, std::string child_path, int fallback_line) const {
  return YamlNode(doc_, value, std::move(child_path), line_of(value, fallback_line));
}

std::string YamlNode::describe() const {
  if (!node_.IsDefined() || node_.IsNull()) return "nothing";
  if (node_.IsMap()) return "a map";
  if (node_.IsSequence()) return fmt::format("a sequence of {}", node_.size());
  std::string text = node_.Scalar();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  const bool numeric_looking = !is_quoted(node_) && parse_double(text).has_value();
  return numeric_looking ? text : "'" + text + "'";
}

void YamlNode::fail_message(const std::string& message) const {
  if (path_.empty()) throw InputError(fmt::format("{}:{}: {}", doc_->file, line_, message));
  throw InputError(fmt::format("{}:{}: {}: {}", doc_->file, line_, path_, message));
}

void YamlNode::fail(const std::string& expected_what) const {
  fail_message(fmt::format("expected {}, got {}", expected_what, describe()));
}

void YamlNode::require_map() const {
  if (!node_.IsMap()) fail("a map");
}

void YamlNode::mark_read(const std::string& key) const {
  Document::ReadMap& record = doc_->read_maps[path_];
  if (record.keys.empty()) {
    record.node = node_;
    record.line = line_;
  }
  record.keys.insert(key);
}

int YamlNode::key_line(const std::string& key) const {
  for (const auto& entry : node_) {
    if (entry.first.IsScalar() && entry.first.Scalar() == key) return line_of(entry.first, line_);
  }
  return line_;
}

bool YamlNode::has(const std::string& key) const {
  return node_.IsMap() && static_cast<const YAML::Node&>(node_)[key].IsDefined();
}

std::vector<std::string> YamlNode::keys() const {
  require_map();
  std::vector<std::string> out;
  for (const auto& entry : node_) out.push_back(entry.first.Scalar());
  return out;
}

YamlNode YamlNode::operator[](const std::string& key) const {
  if (!node_.IsMap()) fail(fmt::format("a map with key '{}'", key));
  mark_read(key);
  const YAML::Node value = static_cast<const YAML::Node&>(node_)[key];
  if (!value.IsDefined()) {
    // A present key that looks like a typo of the missing one says more than "missing".
    if (const auto typo = closest(key, keys()); typo && *typo != key)
      fail_message(fmt::format("missing required key '{}' (found '{}': a typo?)", key, *typo));
    fail_message(fmt::format("missing required key '{}'", key));
  }
  return child(value, path_.empty() ? key : path_ + "." + key, key_line(key));
}

std::optional<YamlNode> YamlNode::optional(const std::string& key) const {
  if (!node_.IsMap()) fail(fmt::format("a map with optional key '{}'", key));
  mark_read(key);
  if (!has(key)) return std::nullopt;
  return (*this)[key];
}

std::size_t YamlNode::size() const {
  if (!node_.IsSequence()) fail("a sequence");
  return node_.size();
}

YamlNode YamlNode::at(std::size_t i) const {
  const std::size_t n = size();
  if (i >= n) fail(fmt::format("a sequence with at least {} entries", i + 1));
  return child(node_[i], fmt::format("{}[{}]", path_, i), line_);
}

double YamlNode::as_double() const {
  if (node_.IsScalar() && !is_quoted(node_)) {
    if (const auto value = parse_double(node_.Scalar())) {
      if (std::abs(*value) > kMaxMagnitude) fail(fmt::format("a number of magnitude at most {:g}", kMaxMagnitude));
      return *value;
    }
  }
  fail("a number");
}

int YamlNode::as_int() const {
  if (node_.IsScalar() && !is_quoted(node_)) {
    if (const auto value = parse_int(node_.Scalar())) return *value;
  }
  fail("an integer");
}

bool YamlNode::as_bool() const {
  if (node_.IsScalar() && !is_quoted(node_)) {
    const std::string& text = node_.Scalar();
    if (text == "true" || text == "True" || text == "TRUE") return true;
    if (text == "false" || text == "False" || text == "FALSE") return false;
  }
  fail("true or false");
}

std::string YamlNode::as_string() const {
  if (!node_.IsScalar()) fail("a string");
  return node_.Scalar();
}

std::vector<double> YamlNode::as_doubles() const {
  if (!node_.IsSequence()) fail("a sequence of numbers");
  std::vector<double> values;
  for (std::size_t i = 0; i < node_.size(); ++i) values.push_back(at(i).as_double());
  return values;
}

Eigen::Vector3d YamlNode::as_vector3() const {
  if (!node_.IsSequence() || node_.size() != 3) fail("a sequence of 3 numbers [x, y, z]");
  return Eigen::Vector3d(at(0).as_double(), at(1).as_double(), at(2).as_double());
}

std::string YamlNode::as_choice(std::initializer_list<std::string_view> choices) const {
  return as_choice(std::vector<std::string>(choices.begin(), choices.end()));
}

std::string YamlNode::as_choice(const std::vector<std::string>& names) const {
  const std::string expected = "one of " + quoted_list(names);
  if (!node_.IsScalar()) fail(expected);
  const std::string& text = node_.Scalar();
  if (std::find(names.begin(), names.end(), text) != names.end()) return text;
  if (const auto guess = closest(text, names)) {
    fail_message(fmt::format("expected {}, got {} (did you mean '{}'?)", expected, describe(), *guess));
  }
  fail(expected);
}

double YamlNode::positive() const { return in_range(0.0, INFINITY, true, true); }

double YamlNode::non_negative() const { return in_range(0.0, INFINITY, false, true); }

double YamlNode::in_range(double lo, double hi, bool lo_open, bool hi_open) const {
  const double value = as_double();
  const bool above_lo = lo_open ? value > lo : value >= lo;
  const bool below_hi = hi_open ? value < hi : value <= hi;
  if (above_lo && below_hi) return value;
  if (std::isinf(hi) && lo == 0.0) fail(lo_open ? "a positive number" : "a non-negative number");
  fail(fmt::format("a number in {}{}, {}{}", lo_open ? '(' : '[', lo, hi, hi_open ? ')' : ']'));
}

int YamlNode::positive_int() const {
  const int value = as_int();
  if (value < 1) fail("a positive integer");
  return value;
}

double YamlNode::get(const std::string& key, double fallback) const {
  const auto value = optional(key);
  return value ? value->as_double() : fallback;
}

int YamlNode::get(const std::string& key, int fallback) const {
  const auto value = optional(key);
  return value ? value->as_int() : fallback;
}

std::string YamlNode::get(const std::string& key, const std::string& fallback) const {
  const auto value = optional(key);
  return value ? value->as_string() : fallback;
}

std::string YamlNode::get(const std::string& key, const char* fallback) const {
  return get(key, std::string(fallback));
}

bool YamlNode::get(const std::string& key, bool fallback) const {
  const auto value = optional(key);
  return value ? value->as_bool() : fallback;
}

void YamlNode::reject_keys_outside(const std::vector<std::string>& known) const {
  require_map();
  for (const auto& entry : node_) {
    const std::string key = entry.first.Scalar();
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    std::string message = fmt::format("unknown key '{}'", key);
    if (const auto guess = closest(key, known)) {
      message += fmt::format(" (did you mean '{}'?)", *guess);
    } else if (!known.empty()) {
      message += fmt::format(" (expected one of {})", quoted_list(known));
    }
    YamlNode at_key(doc_, node_, path_, key_line(key));
    at_key.fail_message(message);
  }
}

void YamlNode::reject_unknown_keys() const {
  const auto it = doc_->read_maps.find(path_);
  std::vector<std::string> known;
  if (it != doc_->read_maps.end()) known.assign(it->second.keys.begin(), it->second.keys.end());
  reject_keys_outside(known);
}

void YamlNode::reject_unknown_keys_everywhere() const {
  // Maps are visited in path order, so the first error reported is deterministic.
  for (const auto& [path, record] : doc_->read_maps) {
    YamlNode(doc_, record.node, path, record.line).reject_unknown_keys();
  }
}

void YamlNode::expect_keys(std::initializer_list<std::string_view> allowed) const {
  reject_keys_outside(std::vector<std::string>(allowed.begin(), allowed.end()));
}

}  // namespace fibrane::io
