#pragma once
// Named numeric parameters of a law or a material as the user gave them: a map of a case file, or
// options of the command line. Laws and materials read their parameters through this interface only, so
// that they know nothing of YAML or CLI11, and every error still names where the bad value came from
// (the YAML implementation in io/yaml_parameters.hpp says file, line and key).
#include <initializer_list>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace fibrane {

class Parameters {
 public:
  virtual ~Parameters() = default;
  virtual bool has(const std::string& key) const = 0;
  // The finite number under `key`; a missing key or a value that is not a number is an InputError.
  virtual double number(const std::string& key) const = 0;
  // The entries of a list of parameter maps under `key` (the terms of a sum law, say); InputError if the
  // key is missing or not a non-empty list of maps.
  virtual std::vector<std::unique_ptr<const Parameters>> list(const std::string& key) const = 0;
  // InputError located at `key` (at the set itself when `key` is empty): "expected <expected>, got ...".
  [[noreturn]] virtual void fail(const std::string& key, const std::string& expected) const = 0;
  // InputError for the first key that is not in `known` (with a "did you mean" suggestion).
  virtual void reject_unknown(std::initializer_list<std::string_view> known) const = 0;

  // Validated reads built on number() and fail().
  double positive(const std::string& key) const;
  double number_or(const std::string& key, double fallback) const;
  double positive_or(const std::string& key, double fallback) const;
  // A number in the interval from lo to hi, each end open or closed.
  double in_range(const std::string& key, double lo, double hi, bool lo_open, bool hi_open) const;
};

// Parameters held in memory (tests, tools); errors name `source` and the key.
class MapParameters final : public Parameters {
 public:
  explicit MapParameters(std::string source, std::map<std::string, double> values = {},
                         std::map<std::string, std::vector<MapParameters>> lists = {});
  bool has(const std::string& key) const override;
  double number(const std::string& key) const override;
  std::vector<std::unique_ptr<const Parameters>> list(const std::string& key) const override;
  [[noreturn]] void fail(const std::string& key, const std::string& expected) const override;
  void reject_unknown(std::initializer_list<std::string_view> known) const override;

 private:
  std::string source_;
  std::map<std::string, double> values_;
  std::map<std::string, std::vector<MapParameters>> lists_;
};

}  // namespace fibrane
