#pragma once
// UTF-8 validation for text read from case files and written to JSON.
#include <cstddef>
#include <string>

namespace fibrane::io {

// Length of the UTF-8 sequence starting at text[i] (1-4), or 0 when it is invalid (overlong forms,
// surrogates and code points above U+10FFFF included).
std::size_t utf8_length(const std::string& text, std::size_t i);

// The first invalid UTF-8 sequence in `text`, or (unless `allow_controls`) the first control character
// other than tab, line feed and carriage return: its byte offset, or npos.
std::size_t find_invalid_utf8(const std::string& text, bool allow_controls);

}  // namespace fibrane::io
