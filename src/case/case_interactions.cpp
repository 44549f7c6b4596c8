#include "case/case_interactions.hpp"

#include <algorithm>

#include "case/case_beam_beam.hpp"
#include "case/case_limits.hpp"
#include "case/case_sbs.hpp"

namespace fibrane::casefile {

using model::Model;

std::string InteractionBody::name() const { return beam ? beam->name() : shell->name(); }

InteractionKinds& InteractionKinds::add(InteractionKind kind) {
  kinds_.push_back(std::move(kind));
  return *this;
}

const InteractionKind* InteractionKinds::find(const std::string& name) const {
  for (const auto& k : kinds_)
    if (k.name == name) return &k;
  return nullptr;
}

const InteractionKind* InteractionKinds::default_for(BodyKind a, BodyKind b) const {
  for (const auto& k : kinds_)
    for (const auto& [x, y] : k.default_for)
      if ((x == a && y == b) || (x == b && y == a)) return &k;
  return nullptr;
}

std::string InteractionKinds::names_text() const {
  std::string out;
  for (const auto& k : kinds_) out += (out.empty() ? "" : ", ") + k.name;
  return out;
}

std::vector<std::string> InteractionKinds::summary_sections() const {
  std::vector<std::string> out;
  for (const auto& k : kinds_)
    for (const auto& s : k.summary_sections)
      if (std::find(out.begin(), out.end(), s) == out.end()) out.push_back(s);
  return out;
}

InteractionKinds& interaction_kinds() {
  static InteractionKinds kinds = [] {
    InteractionKinds k;
    k.add({"sbs", "beam-shell van der Waals coupling by the surrogate beam-shell model (Sec. 5)",
           {{BodyKind::beam, BodyKind::shell}}, {"soft_minimum_points"}, make_sbs});
    k.add({"beam_beam", "fiber-fiber van der Waals and steric interaction by the section-beam potential",
           {{BodyKind::beam, BodyKind::beam}}, {}, make_beam_beam});
    return k;
  }();
  return kinds;
}

namespace {

// The body named at `node`, of any kind.
InteractionBody find_any_body(const Model& m, const io::YamlNode& node) {
  const std::string name = node.as_string();
  for (const auto& s : m.shells)
    if (s.name() == name) return {&s, nullptr, node};
  for (const auto& b : m.beams)
    if (b.name() == name) return {nullptr, &b, node};
  std::string known;
  for (const auto& s : m.shells) known += (known.empty() ? "" : ", ") + s.name();
  for (const auto& b : m.beams) known += (known.empty() ? "" : ", ") + b.name();
  node.fail("the name of a body defined in this case (" + known + ")");
}

// An entry's kind and bodies.
struct Resolved {
  const InteractionKind& kind;
  InteractionBody a, b;
};

// The `between: [a, b]` form: its bodies and its kind (named, or the default for the bodies' kinds).
Resolved read_between(const Model& m, const io::YamlNode& entry) {
  const auto between = entry["between"];
  if (!between.is_sequence() || between.size() != 2)
    between.fail("a list of two body names [a, b] (the same name twice: a body with itself)");
  InteractionBody a = find_any_body(m, between.at(0)), b = find_any_body(m, between.at(1));
  const InteractionKinds& kinds = interaction_kinds();
  if (auto k = entry.optional("kind")) {
    const InteractionKind* kind = kinds.find(k->as_string());
    if (!kind) k->fail("one of " + kinds.names_text());
    return {*kind, a, b};
  }
  const InteractionKind* kind = kinds.default_for(a.kind(), b.kind());
  if (!kind)
    between.fail_message("no interaction kind is the default for a " +
                         std::string(a.kind() == BodyKind::beam ? "beam" : "shell") + " and a " +
                         (b.kind() == BodyKind::beam ? "beam" : "shell") + ": name one with 'kind' (" +
                         kinds.names_text() + ")");
  return {*kind, a, b};
}

// The beam-shell form {beam: B, shell: S}: the SBS kind.
Resolved read_beam_shell(const Model& m, const io::YamlNode& entry) {
  const auto beam_node = entry["beam"], shell_node = entry["shell"];
  const model::BeamBody* beam = nullptr;
  const model::ShellBody* shell = nullptr;
  for (const auto& x : m.beams)
    if (x.name() == beam_node.as_string()) beam = &x;
  for (const auto& x : m.shells)
    if (x.name() == shell_node.as_string()) shell = &x;
  if (!beam) beam_node.fail("the name of a beam defined in this case");
  if (!shell) shell_node.fail("the name of a shell defined in this case");
  return {*interaction_kinds().find("sbs"), {nullptr, beam, beam_node}, {shell, nullptr, shell_node}};
}

}  // namespace

void read_interaction(Model& m, const io::YamlNode& entry) {
  if (!entry.is_map()) entry.fail("a map {between: [a, b], kind: ..., ...} or {beam: B, shell: S, ...}");
  const bool between = entry.has("between");
  if (between && (entry.has("beam") || entry.has("shell")))
    entry.fail_message("name the bodies either as 'between: [a, b]' or as 'beam:' and 'shell:', not both");
  // (InteractionBody holds a YamlNode, which must not be assigned: yaml-cpp's assignment writes into the
  // document.)
  const Resolved r = between ? read_between(m, entry) : read_beam_shell(m, entry);
  const std::string name = entry.has("name") ? read_safe_name(entry["name"]) : r.a.name() + "_" + r.b.name();
  auto interaction = r.kind.make({entry, name, r.a, r.b});
  entry.reject_unknown_keys();
  for (const auto& i : m.interactions())
    if (i->name() == name) {
      if (entry.has("name")) entry["name"].fail("an interaction name not used before");
      entry.fail_message("another interaction is already named '" + name + "' (the default <a>_<b>): give this "
                         "one a 'name'");
    }
  m.add_interaction(std::move(interaction));
}

}  // namespace fibrane::casefile
