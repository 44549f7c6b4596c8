// JSON serialization (escaping, full precision, Python's json module as the independent parser) and
// the progress line (terminal vs plain output, rate limit, ETA).
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <sstream>

#include "io/json.hpp"
#include "io/progress.hpp"
#include "io/scratch_dir.hpp"

namespace fibrane::io {
namespace {

JsonValue sample() {
  JsonValue root = JsonValue::object();
  root.set("name", "quote \" backslash \\ newline \n tab \t bell \x07 micro \xC2\xB5")
      .set("third", 1.0 / 3.0)
      .set("tiny", 5e-324)
      .set("big", 1.5e300)
      .set("steps", 1200)
      .set("converged", true)
      .set("nothing", nullptr);
  root["history"] = std::vector<double>{0.1, -0.25, 1e-10};
  root["nested"]["list"].push_back(JsonValue::object().set("k", "v")).push_back(JsonValue::array());
  root["nested"]["empty"] = JsonValue::object();
  return root;
}

TEST(Json, EscapesStrings) {
  EXPECT_EQ(json_quote("a\"b\\c\nd\x01"), "\"a\\\"b\\\\c\\nd\\u0001\"");
  EXPECT_EQ(JsonValue(std::numeric_limits<double>::quiet_NaN()).dump(), "null");
  EXPECT_EQ(JsonValue(0.1).dump(), "0.1");
}

TEST(Json, InvalidUtf8BecomesTheReplacementCharacter) {
  EXPECT_EQ(json_quote("caf\xc3\xa9"), "\"caf\xc3\xa9\"");          // valid UTF-8 passes through
  EXPECT_EQ(json_quote("caf\xe9!"), "\"caf\\ufffd!\"");              // Latin-1: one byte, one U+FFFD
  EXPECT_EQ(json_quote("\xc0\xaf\x7f"), "\"\\ufffd\\ufffd\\u007f\""); // overlong form, DEL
  EXPECT_EQ(json_quote("\xf0\x9f\x98"), "\"\\ufffd\\ufffd\\ufffd\""); // truncated 4-byte sequence
}

TEST(Json, PrettyLayout) {
  JsonValue v = JsonValue::object();
  v.set("a", 1).set("b", JsonValue::array({1.5, "x"}));
  v["c"]["d"] = false;
  EXPECT_EQ(v.dump(2), "{\n  \"a\": 1,\n  \"b\": [1.5, \"x\"],\n  \"c\": {\n    \"d\": false\n  }\n}");
  EXPECT_EQ(v.dump(-1), "{\"a\":1,\"b\":[1.5,\"x\"],\"c\":{\"d\":false}}");
  v.set("a", 2);  // replacing keeps the member's position
  EXPECT_EQ(v.dump(-1), "{\"a\":2,\"b\":[1.5,\"x\"],\"c\":{\"d\":false}}");
  EXPECT_THROW(v["b"]["x"], std::logic_error);
}

// Python parses our pretty output and re-serializes it compactly; Python writes floats as their
// shortest round-trip repr like we do, so the text must be identical to our compact dump.
TEST(Json, PythonParsesAndReproducesIt) {
  if (!testing::python_has("json")) GTEST_SKIP() << "/usr/bin/python3 not available";
  testing::ScratchDir dir;
  const JsonValue value = sample();
  testing::write_text(dir.file("in.json"), value.dump(2));
  const std::string command = "/usr/bin/python3 -c 'import json,sys; "
                              "v=json.load(open(sys.argv[1],encoding=\"utf-8\")); "
                              "open(sys.argv[2],\"w\",encoding=\"utf-8\").write("
                              "json.dumps(v,ensure_ascii=False,separators=(\",\",\":\")))' " +
                              dir.file("in.json") + " " + dir.file("out.json");
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(testing::read_text(dir.file("out.json")), value.dump(-1));
}

TEST(Progress, FormatsEtaFromTimeRate) {
  std::ostringstream sink;
  const ProgressLine progress(1.0, sink, false);
  // A quarter of the simulated time took 10 s, so the remaining three quarters take 30 s.
  const std::string line = progress.format(7, 0.25, 3, 1.5e-9, std::chrono::seconds(10));
  EXPECT_NE(line.find("step     7"), std::string::npos) << line;
  EXPECT_NE(line.find("t = 2.5000e-01 / 1.0000e+00 ( 25.0%)"), std::string::npos) << line;
  EXPECT_NE(line.find("newton  3"), std::string::npos) << line;
  EXPECT_NE(line.find("|r| = 1.50e-09"), std::string::npos) << line;
  EXPECT_NE(line.find("ETA 30s"), std::string::npos) << line;
  EXPECT_EQ(format_duration(185), "3m05s");
  EXPECT_EQ(format_duration(7620), "2h07m");
  EXPECT_EQ(format_duration(-1), "?");
}

TEST(Progress, PathsThatTurnBackShowElapsedTimeInsteadOfAnEta) {
  std::ostringstream sink;
  ProgressLine progress(1.0, sink, false);
  progress.set_monotone(false);
  const std::string line = progress.format(12, 0.25, 3, 1.5e-9, std::chrono::seconds(10));
  EXPECT_NE(line.find("t = 2.5000e-01 (end 1.0000e+00)"), std::string::npos) << line;
  EXPECT_NE(line.find("elapsed 10s"), std::string::npos) << line;
  EXPECT_EQ(line.find("ETA"), std::string::npos) << line;
  EXPECT_EQ(line.find("%"), std::string::npos) << line;
}

TEST(Progress, PlainOutputIsRateLimited) {
  std::ostringstream sink;
  ProgressLine progress(1.0, sink, false, std::chrono::hours(1), std::chrono::hours(1));
  progress.update(1, 0.1, 2, 1e-3);
  progress.update(2, 0.2, 2, 1e-3);  // within the interval: suppressed
  progress.finish("done");
  const std::string text = sink.str();
  EXPECT_EQ(text.find('\r'), std::string::npos);
  EXPECT_NE(text.find("step     1"), std::string::npos);
  EXPECT_EQ(text.find("step     2"), std::string::npos);
  EXPECT_EQ(text.substr(text.size() - 5), "done\n");
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2);
}

TEST(Progress, TerminalOutputOverwritesOneLine) {
  std::ostringstream sink;
  ProgressLine progress(2.0, sink, true, std::chrono::seconds(0));
  progress.update(1, 0.5, 4, 1e-6);
  progress.update(2, 1.0, 3, 1e-7);
  progress.finish("finished");
  const std::string text = sink.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\r'), 3);  // two updates and the final clear
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1);  // only the final message ends a line
  EXPECT_EQ(text.substr(text.size() - 13), "\r\x1b[Kfinished\n");
}

}  // namespace
}  // namespace fibrane::io
