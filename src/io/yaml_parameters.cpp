#include "io/yaml_parameters.hpp"

namespace fibrane::io {

YamlParameters::YamlParameters(YamlNode node, std::vector<std::string> ignored)
    : node_(std::move(node)), ignored_(std::move(ignored)) {
  if (!node_.is_map()) node_.fail("a map of parameters");
}

std::vector<std::unique_ptr<const Parameters>> YamlParameters::list(const std::string& key) const {
  const YamlNode l = node_[key];
  if (!l.is_sequence() || l.size() == 0) l.fail("a non-empty list of maps");
  std::vector<std::unique_ptr<const Parameters>> out;
  for (std::size_t i = 0; i < l.size(); ++i) out.push_back(std::make_unique<YamlParameters>(l.at(i)));
  return out;
}

void YamlParameters::fail(const std::string& key, const std::string& expected) const {
  if (key.empty()) node_.fail(expected);
  if (node_.has(key)) node_[key].fail(expected);
  node_.fail_message("missing key '" + key + "': expected " + expected);
}

void YamlParameters::reject_unknown(std::initializer_list<std::string_view> known) const {
  std::vector<std::string_view> all(known);
  for (const auto& k : ignored_) all.push_back(k);
  for (const auto& key : node_.keys()) {
    bool ok = false;
    for (auto k : all) ok |= (k == key);
    if (!ok) {
      // Let the strict reader produce its located "unknown key (did you mean ...)" message.
      for (auto k : all) (void)node_.optional(std::string(k));
      node_.reject_unknown_keys();
    }
  }
}

}  // namespace fibrane::io
