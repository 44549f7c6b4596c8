#pragma once
// Checks a case file's raw text before it is parsed into a tree, so that hostile input is refused with a
// located message instead of exhausting memory or time:
//   - at most kMaxYamlBytes bytes (read_text_limited refuses a larger file before reading it whole);
//   - valid UTF-8 without control characters other than tab, line feed and carriage return;
//   - exactly one YAML document; no anchors (&a), aliases (*a) or explicit tags (!!str, !foo): a case file
//     has no use for them, and aliases expand exponentially ("billion laughs");
//   - at most kMaxYamlNodes nodes, nested at most kMaxYamlDepth deep.
// Every refusal throws fibrane::InputError "<file>:<line>: <what>".
#include <cstddef>
#include <string>

namespace fibrane::io {

inline constexpr std::size_t kMaxYamlBytes = 16u << 20;  // 16 MiB
inline constexpr std::size_t kMaxYamlNodes = 1'000'000;
inline constexpr int kMaxYamlDepth = 64;

// Reads the file at `path`, refusing a missing or unreadable file, anything but a regular file (a
// directory, a FIFO, a device: refused without blocking) and a file larger than kMaxYamlBytes.
std::string read_text_limited(const std::string& path);

// Checks encoding and YAML structure of `text` as described above; `source_name` names it in messages.
void check_yaml_text(const std::string& text, const std::string& source_name);

}  // namespace fibrane::io
