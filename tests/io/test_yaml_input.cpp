// Every YAML input error must name the file, the line, the key path, what was expected and what was
// found. Messages are compared in full, so any change of wording, line or path makes these tests fail.
#include <gtest/gtest.h>

#include <functional>

#include "common/error.hpp"
#include "io/scratch_dir.hpp"
#include "io/yaml_input.hpp"

namespace fibrane::io {
namespace {

// Line numbers are part of the expectations below; keep this text in sync with them.
const char* const kCase =
    "# demo case\n"                  // 1
    "name: demo\n"                   // 2
    "time:\n"                        // 3
    "  end: 1.5\n"                   // 4
    "  steps: 10\n"                  // 5
    "solver: newtn\n"                // 6
    "origin: [0, 0.5, -2]\n"         // 7
    "shells:\n"                      // 8
    "  - thicknes: 0.1\n"            // 9
    "    material:\n"                // 10
    "      young: 1.0e6\n"           // 11
    "      poisson: 0.7\n"           // 12
    "    label: \"3.5\"\n"           // 13
    "    count: 2.5\n"               // 14
    "    flag: yes\n"                // 15
    "axis: [1, 2]\n";                // 16

YamlNode load() { return YamlNode::load_string(kCase, "case.yaml"); }

// Runs `action`, which must throw InputError, and returns its message.
std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

TEST(YamlInput, ReadsValuesAndPaths) {
  const YamlNode root = load();
  EXPECT_EQ(root["name"].as_string(), "demo");
  EXPECT_EQ(root["time"]["end"].as_double(), 1.5);
  EXPECT_EQ(root["time"]["steps"].as_int(), 10);
  EXPECT_EQ(root["origin"].as_vector3(), Eigen::Vector3d(0, 0.5, -2));
  EXPECT_EQ(root["axis"].as_doubles(), (std::vector<double>{1, 2}));
  const YamlNode material = root["shells"].at(0)["material"];
  EXPECT_EQ(material.path(), "shells[0].material");
  EXPECT_EQ(material["young"].line(), 11);
  EXPECT_EQ(material["young"].positive(), 1.0e6);
  EXPECT_EQ(root["shells"].size(), 1u);
  EXPECT_TRUE(root.is_map());
  EXPECT_TRUE(root["shells"].is_sequence());
  EXPECT_TRUE(root["name"].is_scalar());
}

TEST(YamlInput, DefaultsApplyOnlyToAbsentKeys) {
  const YamlNode time = load()["time"];
  EXPECT_EQ(time.get("end", 9.0), 1.5);
  EXPECT_EQ(time.get("start", 0.25), 0.25);
  EXPECT_EQ(time.get("steps", 3), 10);
  EXPECT_EQ(time.get("substeps", 3), 3);
  EXPECT_EQ(time.get("scheme", "implicit"), "implicit");
  EXPECT_EQ(time.get("scheme", std::string("x")), "x");
  EXPECT_TRUE(time.get("adaptive", true));
  EXPECT_FALSE(time.has("adaptive"));
  EXPECT_FALSE(time.optional("adaptive").has_value());
  // A present key with a wrong type is an error, not silently the default.
  EXPECT_EQ(error_of([] { load().get("name", 1.0); }),
            "case.yaml:2: name: expected a number, got 'demo'");
}

TEST(YamlInput, MissingKeyNamesMapAndKey) {
  EXPECT_EQ(error_of([] { load()["shells"].at(0)["material"]["density"]; }),
            "case.yaml:11: shells[0].material: missing required key 'density'");
  EXPECT_EQ(error_of([] { load()["gravity"]; }), "case.yaml:2: missing required key 'gravity'");
}

TEST(YamlInput, WrongTypes) {
  const YamlNode root = load();
  const YamlNode shell = root["shells"].at(0);
  EXPECT_EQ(error_of([&] { root["name"].as_double(); }), "case.yaml:2: name: expected a number, got 'demo'");
  // Quoted numbers are strings: the user wrote a string.
  EXPECT_EQ(error_of([&] { shell["label"].as_double(); }),
            "case.yaml:13: shells[0].label: expected a number, got '3.5'");
  EXPECT_EQ(error_of([&] { shell["count"].as_int(); }),
            "case.yaml:14: shells[0].count: expected an integer, got 2.5");
  EXPECT_EQ(error_of([&] { shell["flag"].as_bool(); }),
            "case.yaml:15: shells[0].flag: expected true or false, got 'yes'");
  EXPECT_EQ(error_of([&] { root["time"].as_double(); }), "case.yaml:4: time: expected a number, got a map");
  EXPECT_EQ(error_of([&] { root["time"].size(); }), "case.yaml:4: time: expected a sequence, got a map");
  EXPECT_EQ(error_of([&] { root["name"]["x"]; }), "case.yaml:2: name: expected a map with key 'x', got 'demo'");
  EXPECT_EQ(error_of([&] { root["shells"].at(3); }),
            "case.yaml:9: shells: expected a sequence with at least 4 entries, got a sequence of 1");
}

TEST(YamlInput, OutOfRangeMatchesTheDocumentedFormat) {
  const YamlNode poisson = load()["shells"].at(0)["material"]["poisson"];
  EXPECT_EQ(error_of([&] { poisson.in_range(-1, 0.5, true, true); }),
            "case.yaml:12: shells[0].material.poisson: expected a number in (-1, 0.5), got 0.7");
  EXPECT_EQ(error_of([&] { poisson.in_range(0, 0.5, false, false); }),
            "case.yaml:12: shells[0].material.poisson: expected a number in [0, 0.5], got 0.7");
  EXPECT_EQ(poisson.in_range(0, 0.7, false, false), 0.7);  // closed bound admits the end point
  EXPECT_EQ(error_of([&] { poisson.in_range(0, 0.7, false, true); }),
            "case.yaml:12: shells[0].material.poisson: expected a number in [0, 0.7), got 0.7");
  const YamlNode z = load()["origin"].at(2);
  EXPECT_EQ(z.path(), "origin[2]");
  EXPECT_EQ(error_of([&] { z.positive(); }), "case.yaml:7: origin[2]: expected a positive number, got -2");
}

TEST(YamlInput, Vector3NeedsExactlyThreeNumbers) {
  EXPECT_EQ(error_of([] { load()["axis"].as_vector3(); }),
            "case.yaml:16: axis: expected a sequence of 3 numbers [x, y, z], got a sequence of 2");
  EXPECT_EQ(error_of([] { load()["name"].as_vector3(); }),
            "case.yaml:2: name: expected a sequence of 3 numbers [x, y, z], got 'demo'");
}

TEST(YamlInput, BadChoiceSuggestsTheClosest) {
  EXPECT_EQ(error_of([] { load()["solver"].as_choice({"newton", "arc_length"}); }),
            "case.yaml:6: solver: expected one of 'newton', 'arc_length', got 'newtn' (did you mean 'newton'?)");
  EXPECT_EQ(error_of([] { load()["name"].as_choice({"newton", "arc_length"}); }),
            "case.yaml:2: name: expected one of 'newton', 'arc_length', got 'demo'");
  EXPECT_EQ(load()["solver"].as_choice({"newtn", "x"}), "newtn");
}

TEST(YamlInput, UnknownKeySuggestsTheClosestReadKey) {
  const YamlNode root = load();
  const YamlNode shell = root["shells"].at(0);
  shell["material"];
  shell.get("thickness", 0.2);  // asked for but absent: still a known name for suggestions
  shell.optional("label");
  shell.optional("count");
  // A different node object for the same map shares the record of read keys.
  root["shells"].at(0).optional("flag");
  EXPECT_EQ(error_of([&] { root["shells"].at(0).reject_unknown_keys(); }),
            "case.yaml:9: shells[0]: unknown key 'thicknes' (did you mean 'thickness'?)");
  EXPECT_EQ(error_of([&] { root["time"].expect_keys({"end", "dt"}); }),
            "case.yaml:5: time: unknown key 'steps' (expected one of 'end', 'dt')");
  root["time"].expect_keys({"end", "steps"});  // all keys allowed: no throw
  const YamlNode time = root["time"];
  time["end"];
  time.get("steps", 1);
  time.reject_unknown_keys();
}

TEST(YamlInput, UnknownKeysEverywhereChecksEveryReadMap) {
  const YamlNode root = YamlNode::load_string("a:\n  b:\n    c: 1\n    cc: 2\n  d: 3\ne: 4\n", "u.yaml");
  root["a"]["b"]["c"].as_int();
  root["e"].as_int();
  // Map "a" is fine only once 'd' is read; map "a.b" still has the unread 'cc'.
  EXPECT_EQ(error_of([&] { root.reject_unknown_keys_everywhere(); }),
            "u.yaml:5: a: unknown key 'd' (expected one of 'b')");
  root["a"].get("d", 0);
  EXPECT_EQ(error_of([&] { root.reject_unknown_keys_everywhere(); }),
            "u.yaml:4: a.b: unknown key 'cc' (did you mean 'c'?)");
  root["a"]["b"]["cc"];
  root.reject_unknown_keys_everywhere();
}

TEST(YamlInput, SyntaxErrorsAndMissingFilesNameTheFile) {
  testing::ScratchDir dir;
  const std::string path = dir.file("broken.yaml");
  testing::write_text(path, "a: 1\nb: [1, 2\nc: 3\n");
  const std::string message = error_of([&] { YamlNode::load_file(path); });
  // yaml-cpp reports an unclosed flow sequence where it gives up; the line must be a real one (2 or 3).
  EXPECT_TRUE(message.rfind(path + ":3: YAML syntax error: ", 0) == 0 ||
              message.rfind(path + ":2: YAML syntax error: ", 0) == 0)
      << message;
  testing::write_text(path, "a: 1\n  b: 2\n");
  EXPECT_EQ(error_of([&] { YamlNode::load_file(path); }).rfind(path + ":2: YAML syntax error: ", 0), 0u);
  EXPECT_EQ(error_of([&] { YamlNode::load_file(dir.file("absent.yaml")); }),
            dir.file("absent.yaml") + ": cannot open the file for reading");
  testing::write_text(path, "a: 1\nb:\n  c: 2\n  c: 3\n");
  EXPECT_EQ(error_of([&] { YamlNode::load_file(path); }), path + ":4: duplicate key 'c'");
  testing::write_text(path, "a: 1\nb: 2.5\n");
  const YamlNode ok = YamlNode::load_file(path);
  EXPECT_EQ(ok.file(), path);
  EXPECT_EQ(ok["b"].as_double(), 2.5);
}

TEST(YamlInput, StrictScalars) {
  const YamlNode root = YamlNode::load_string("a: 1e3\nb: +2\nc: .inf\nd: 0x10\ne: true\nf: ~\ng: 3000000000\n", "s.yaml");
  EXPECT_EQ(root["a"].as_double(), 1000.0);
  EXPECT_EQ(error_of([&] { root["a"].as_int(); }), "s.yaml:1: a: expected an integer, got 1e3");
  EXPECT_EQ(root["b"].as_int(), 2);
  EXPECT_EQ(error_of([&] { root["c"].as_double(); }), "s.yaml:3: c: expected a number, got '.inf'");
  EXPECT_EQ(error_of([&] { root["d"].as_double(); }), "s.yaml:4: d: expected a number, got '0x10'");
  EXPECT_TRUE(root["e"].as_bool());
  EXPECT_EQ(error_of([&] { root["f"].as_string(); }), "s.yaml:6: f: expected a string, got nothing");
  EXPECT_EQ(error_of([&] { root["g"].positive_int(); }), "s.yaml:7: g: expected an integer, got 3000000000");
}

TEST(YamlInput, MagnitudesAbove1e100AreRefused) {
  const YamlNode root = YamlNode::load_string("a: 1e100\nb: -1e101\n", "s.yaml");
  EXPECT_EQ(root["a"].as_double(), 1e100);
  EXPECT_EQ(error_of([&] { root["b"].as_double(); }),
            "s.yaml:2: b: expected a number of magnitude at most 1e+100, got -1e101");
}

TEST(YamlInput, HostileTextIsRefusedWithItsLine) {
  auto load = [](const std::string& text) { return error_of([&] { YamlNode::load_string(text, "h.yaml"); }); };
  EXPECT_EQ(load("a: 1\nb: !!str 5\n"),
            "h.yaml:2: explicit YAML tags ('tag:yaml.org,2002:str') are not allowed in a case file: write plain values");
  EXPECT_NE(load("a: &x 1\nb: *x\n").find("h.yaml:1: YAML anchors (&name) are not allowed"), std::string::npos);
  EXPECT_NE(load("a: 1\n---\nb: 2\n").find("h.yaml:2: a second YAML document"), std::string::npos);
  EXPECT_EQ(load("a: 1\nt: \"caf\xe9\"\n"),
            "h.yaml:2: invalid UTF-8 (byte 0xE9 at offset 12): a case file must be UTF-8 text");
  EXPECT_NE(load("a: 1\n\x01\n").find("h.yaml:2: a control character (byte 0x01"), std::string::npos);
  EXPECT_NE(load("a: " + std::string(100, '[') + std::string(100, ']')).find("nested more than 64 deep"),
            std::string::npos);
  EXPECT_NO_THROW(YamlNode::load_string("t: \"caf\xc3\xa9\"\n", "h.yaml")) << "valid UTF-8 passes";
}

TEST(YamlInput, EditDistance) {
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("thicknes", "thickness"), 1u);
  EXPECT_EQ(edit_distance("same", "same"), 0u);
}

}  // namespace
}  // namespace fibrane::io
