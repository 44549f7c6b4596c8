#pragma once
// Strict, self-locating access to a YAML case file.
//
// Every error throws fibrane::InputError whose message names the file, the line, the key path, what
// was expected and what was found, e.g.
//   case.yaml:12: shells[0].material.poisson: expected a number in (-1, 0.5), got 0.7
// Reading is strict: numbers must be plain (unquoted) finite scalars, integers must have no fractional
// part, booleans are exactly true/false, duplicate keys are rejected at load time, and a map whose keys
// were not all read can be rejected with reject_unknown_keys() ("did you mean ...?").
//
// Typical use:
//   const YamlNode root = YamlNode::load_file(path);
//   const YamlNode material = root["shell"]["material"];
//   const double young = material["young"].positive();
//   const double poisson = material["poisson"].in_range(-1.0, 0.5, true, true);
//   const double density = material.get("density", 1.0);
//   ...
//   root.reject_unknown_keys_everywhere();   // or material.reject_unknown_keys() per map
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cstddef>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fibrane::io {

class YamlNode {
 public:
  // Parses the whole file. A missing/unreadable file, a syntax error (with its line) and text that
  // io/yaml_guard.hpp refuses (size, encoding, anchors, aliases, tags, several documents) are InputErrors.
  static YamlNode load_file(const std::string& path);
  // Same, from text already in memory; `source_name` stands in for the file name in messages.
  static YamlNode load_string(const std::string& text, const std::string& source_name);

  const std::string& path() const { return path_; }  // e.g. "shells[0].material"; "" for the root
  const std::string& file() const;
  int line() const { return line_; }  // 1-based

  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }
  bool is_null() const { return node_.IsNull(); }

  // Maps. has() does not count as reading the key; operator[], optional() and get() do (even when the
  // key is absent, so that the key becomes a known name for "did you mean" suggestions).
  bool has(const std::string& key) const;
  YamlNode operator[](const std::string& key) const;  // required key: missing -> InputError
  std::optional<YamlNode> optional(const std::string& key) const;
  std::vector<std::string> keys() const;  // in file order; does not mark them as read

  // Sequences.
  std::size_t size() const;  // sequence length (InputError if not a sequence)
  YamlNode at(std::size_t i) const;

  // Scalars.
  // Finite number of magnitude at most kMaxMagnitude: larger values overflow products of a few of them
  // (stiffness, loads) to infinity.
  double as_double() const;
  static constexpr double kMaxMagnitude = 1e100;
  int as_int() const;
  bool as_bool() const;
  std::string as_string() const;
  std::vector<double> as_doubles() const;  // sequence of numbers
  Eigen::Vector3d as_vector3() const;      // [x, y, z]
  std::string as_choice(std::initializer_list<std::string_view> choices) const;
  std::string as_choice(const std::vector<std::string>& choices) const;

  // Validated numbers.
  double positive() const;  // > 0
  double non_negative() const;  // >= 0
  double in_range(double lo, double hi, bool lo_open, bool hi_open) const;
  int positive_int() const;  // >= 1

  // Optional keys with defaults; a present key must still have the right type.
  double get(const std::string& key, double fallback) const;
  int get(const std::string& key, int fallback) const;
  std::string get(const std::string& key, const std::string& fallback) const;
  std::string get(const std::string& key, const char* fallback) const;
  bool get(const std::string& key, bool fallback) const;

  // Strict schema: every key of this map never read through this node or any other node for the same
  // path is an error: "unknown key 'thicknes' (did you mean 'thickness'?)". Call after reading a map.
  void reject_unknown_keys() const;
  // The same check for every map of the document that was read from (through any node): one call after
  // the whole case has been read. Maps never read from are not checked; their own key is, in the parent.
  void reject_unknown_keys_everywhere() const;
  // Alternative: the allowed keys are listed explicitly.
  void expect_keys(std::initializer_list<std::string_view> allowed) const;

  // InputError at this node: "<file>:<line>: <path>: expected <expected_what>, got <what is here>".
  [[noreturn]] void fail(const std::string& expected_what) const;
  // InputError at this node with a free-form message: "<file>:<line>: <path>: <message>".
  [[noreturn]] void fail_message(const std::string& message) const;

  // A short description of the value here, as used after "got": "0.7", "'abc'", "a map", "nothing".
  std::string describe() const;

 private:
  struct Document;  // shared by every node of one file: file name and the keys read per map path
  YamlNode(std::shared_ptr<Document> doc, YAML::Node node, std::string path, int line);
  YamlNode child(const YAML::Node& value, std::string child_path, int fallback_line) const;
  void require_map() const;
  void mark_read(const std::string& key) const;
  int key_line(const std::string& key) const;
  void reject_keys_outside(const std::vector<std::string>& known) const;

  std::shared_ptr<Document> doc_;
  YAML::Node node_;
  std::string path_;
  int line_ = 0;
};

// Levenshtein edit distance, used for "did you mean" suggestions.
std::size_t edit_distance(std::string_view a, std::string_view b);

}  // namespace fibrane::io
