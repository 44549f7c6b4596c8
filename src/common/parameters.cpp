#include "common/parameters.hpp"

#include <cmath>

#include "common/error.hpp"
#include "common/format.hpp"

namespace fibrane {

double Parameters::positive(const std::string& key) const {
  const double v = number(key);
  if (!(v > 0)) fail(key, "a positive number");
  return v;
}

double Parameters::number_or(const std::string& key, double fallback) const {
  return has(key) ? number(key) : fallback;
}

double Parameters::positive_or(const std::string& key, double fallback) const {
  return has(key) ? positive(key) : fallback;
}

double Parameters::in_range(const std::string& key, double lo, double hi, bool lo_open, bool hi_open) const {
  const double v = number(key);
  const bool above = lo_open ? v > lo : v >= lo;
  const bool below = hi_open ? v < hi : v <= hi;
  if (!above || !below)
    fail(key, "a number in " + std::string(lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) +
                  (hi_open ? ")" : "]"));
  return v;
}

MapParameters::MapParameters(std::string source, std::map<std::string, double> values,
                             std::map<std::string, std::vector<MapParameters>> lists)
    : source_(std::move(source)), values_(std::move(values)), lists_(std::move(lists)) {}

bool MapParameters::has(const std::string& key) const { return values_.count(key) || lists_.count(key); }

double MapParameters::number(const std::string& key) const {
  const auto it = values_.find(key);
  if (it == values_.end()) fail(key, "a number");
  if (!std::isfinite(it->second)) fail(key, "a finite number");
  return it->second;
}

std::vector<std::unique_ptr<const Parameters>> MapParameters::list(const std::string& key) const {
  const auto it = lists_.find(key);
  if (it == lists_.end() || it->second.empty()) fail(key, "a non-empty list");
  std::vector<std::unique_ptr<const Parameters>> out;
  for (const auto& p : it->second) out.push_back(std::make_unique<MapParameters>(p));
  return out;
}

void MapParameters::fail(const std::string& key, const std::string& expected) const {
  std::string got = "nothing";
  if (const auto it = values_.find(key); it != values_.end()) got = format_number(it->second);
  throw InputError(source_ + (key.empty() ? "" : ": " + key) + ": expected " + expected + ", got " + got);
}

void MapParameters::reject_unknown(std::initializer_list<std::string_view> known) const {
  auto check = [&](const std::string& key) {
    for (auto k : known)
      if (k == key) return;
    throw InputError(source_ + ": unknown parameter '" + key + "'");
  };
  for (const auto& [key, value] : values_) check(key);
  for (const auto& [key, value] : lists_) check(key);
}

}  // namespace fibrane
