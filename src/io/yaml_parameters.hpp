#pragma once
// Parameters (common/parameters.hpp) read from a map of a YAML case file: errors name the file, the line
// and the key path, like every other case-file error.
#include "common/parameters.hpp"
#include "io/yaml_input.hpp"

namespace fibrane::io {

class YamlParameters final : public Parameters {
 public:
  // `node` must be a map; `ignored` are keys of the map that belong to the caller (e.g. `model`), which
  // reject_unknown() accepts.
  explicit YamlParameters(YamlNode node, std::vector<std::string> ignored = {});
  bool has(const std::string& key) const override { return node_.has(key); }
  double number(const std::string& key) const override { return node_[key].as_double(); }
  std::vector<std::unique_ptr<const Parameters>> list(const std::string& key) const override;
  [[noreturn]] void fail(const std::string& key, const std::string& expected) const override;
  void reject_unknown(std::initializer_list<std::string_view> known) const override;

 private:
  YamlNode node_;
  std::vector<std::string> ignored_;
};

}  // namespace fibrane::io
