#pragma once
// A table of named factories: interaction laws, shell materials and continuation methods are chosen by
// name in a case file and built from their parameters. Each kind keeps one registry, filled in one
// function with one line per entry, so that adding a law or a material is one new file plus one line.
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "common/parameters.hpp"

namespace fibrane {

template <class Product, class... Context>
class Registry {
 public:
  using Factory = std::function<Product(const Parameters&, Context...)>;
  struct Entry {
    std::string name, summary;
    Factory make;
  };

  Registry& add(std::string name, std::string summary, Factory make) {
    entries_.push_back({std::move(name), std::move(summary), std::move(make)});
    return *this;
  }
  const Entry* find(const std::string& name) const {
    for (const auto& e : entries_)
      if (e.name == name) return &e;
    return nullptr;
  }
  // Builds the entry `name`; an unknown name is an InputError listing the known ones.
  Product make(const std::string& name, const Parameters& p, Context... context) const {
    const Entry* e = find(name);
    if (!e) p.fail("", "one of " + names_text() + " (got '" + name + "')");
    return e->make(p, context...);
  }
  const std::vector<Entry>& entries() const { return entries_; }
  std::string names_text() const {
    std::string out;
    for (const auto& e : entries_) out += (out.empty() ? "" : ", ") + e.name;
    return out;
  }

 private:
  std::vector<Entry> entries_;
};

}  // namespace fibrane
