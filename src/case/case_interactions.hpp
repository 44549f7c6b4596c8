#pragma once
// The kinds of interaction a case can name (interactions[].kind), each registered once in
// case_interactions.cpp with the factory that reads its entry and builds the model::Interaction from the
// two bodies it names. The case reader and the output ask the registry, so a new kind is a class deriving
// from model::Interaction, a factory, and one registration (programs and tests may add kinds at run time).
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "io/yaml_input.hpp"
#include "model/model.hpp"

namespace fibrane::casefile {

enum class BodyKind { shell, beam };

// A body an interaction entry names, with the node that names it (for located errors).
struct InteractionBody {
  const model::ShellBody* shell = nullptr;
  const model::BeamBody* beam = nullptr;
  io::YamlNode at;
  BodyKind kind() const { return beam ? BodyKind::beam : BodyKind::shell; }
  std::string name() const;
};

// What a kind's factory receives: the case entry (the factory reads its own keys; the reader rejects
// the keys nobody read once the factory returns), the interaction's name and its two bodies, in the
// order the entry gives them (the same body twice for a body with itself).
struct InteractionRequest {
  const io::YamlNode& entry;
  std::string name;
  InteractionBody a, b;
};

// One kind of the registry.
struct InteractionKind {
  std::string name;     // the value of interactions[].kind
  std::string summary;  // one line for messages and docs
  // The pairs of body kinds (in either order) whose entries get this kind when they name none.
  std::vector<std::pair<BodyKind, BodyKind>> default_for;
  // The top-level summary.json sections its interactions may fill (model::Interaction::summary_sections).
  std::vector<std::string> summary_sections;
  std::function<std::unique_ptr<model::Interaction>(const InteractionRequest&)> make;
};

class InteractionKinds {
 public:
  InteractionKinds& add(InteractionKind kind);
  const InteractionKind* find(const std::string& name) const;
  // The first kind that is the default for bodies of kinds a and b; null if none.
  const InteractionKind* default_for(BodyKind a, BodyKind b) const;
  std::string names_text() const;
  // Every kind's summary sections, in registration order, each once.
  std::vector<std::string> summary_sections() const;

 private:
  std::vector<InteractionKind> kinds_;
};

// The registry (built-in kinds: sbs); mutable so that programs and tests may add their own.
InteractionKinds& interaction_kinds();

// Reads one entry of `interactions` and adds its interaction to the model: either
//   {between: [a, b], kind: K, name: N, ...}  (kind optional: the default for the bodies' kinds), or
//   {beam: B, shell: S, name: N, ...}          (the beam-shell SBS coupling).
// The name defaults to <a>_<b> (<beam>_<shell>) and must be new. InputError located at the entry's keys.
void read_interaction(model::Model& m, const io::YamlNode& entry);

}  // namespace fibrane::casefile
