#include "run/partition_report.hpp"

namespace fibrane::run {

io::JsonValue partition_json(const solve::ElementPartition& p) {
  io::JsonValue j = io::JsonValue::object();
  j.set("method", p.method == solve::Partitioning::graph ? "graph" : "contiguous");
  if (!p.note.empty()) j.set("note", p.note);
  j.set("processes", p.unknowns.processes());
  io::JsonValue elements = io::JsonValue::array(), unknowns = io::JsonValue::array();
  for (int count : p.elements) elements.push_back(count);
  for (int q = 0; q < p.unknowns.processes(); ++q) unknowns.push_back(p.unknowns.count(q));
  j.set("elements", std::move(elements)).set("owned_unknowns", std::move(unknowns));
  j.set("element_weight", io::JsonValue(p.weight));
  j.set("interface_unknowns", p.interface_unknowns).set("imbalance", p.imbalance);
  return j;
}

}  // namespace fibrane::run
