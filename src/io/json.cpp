#include "io/json.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "io/csv.hpp"
#include "io/utf8.hpp"

namespace fibrane::io {

JsonValue::JsonValue(const std::vector<double>& numbers) : kind_(Kind::array) {
  values_.assign(numbers.begin(), numbers.end());
}

JsonValue JsonValue::array(std::initializer_list<JsonValue> items) {
  JsonValue value;
  value.kind_ = Kind::array;
  value.values_.assign(items.begin(), items.end());
  return value;
}

JsonValue JsonValue::object() {
  JsonValue value;
  value.kind_ = Kind::object;
  return value;
}

void JsonValue::become(Kind kind) {
  if (kind_ == Kind::null) kind_ = kind;
  if (kind_ != kind) {
    throw std::logic_error(kind == Kind::object ? "JsonValue: not an object" : "JsonValue: not an array");
  }
}

JsonValue& JsonValue::set(const std::string& key, JsonValue value) {
  (*this)[key] = std::move(value);
  return *this;
}

JsonValue& JsonValue::operator[](const std::string& key) {
  become(Kind::object);
  for (std::size_t i = 0; i < keys_.size(); ++i) {
    if (keys_[i] == key) return values_[i];
  }
  keys_.push_back(key);
  values_.emplace_back();
  return values_.back();
}

JsonValue& JsonValue::push_back(JsonValue value) {
  become(Kind::array);
  values_.push_back(std::move(value));
  return *this;
}

std::size_t JsonValue::size() const {
  return kind_ == Kind::array || kind_ == Kind::object ? values_.size() : 0;
}

std::vector<std::pair<std::string, JsonValue>> JsonValue::members() const {
  std::vector<std::pair<std::string, JsonValue>> out;
  if (kind_ != Kind::object) return out;
  for (std::size_t i = 0; i < keys_.size(); ++i) out.emplace_back(keys_[i], values_[i]);
  return out;
}

std::string json_quote(const std::string& text) {
  std::string out = "\"";
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) {
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(c)));
        } else if (static_cast<unsigned char>(c) < 0x80) {
          out += c;
        } else if (const std::size_t n = utf8_length(text, i); n > 0) {
          out.append(text, i, n);
          i += n - 1;
        } else {
          out += "\\ufffd";  // not UTF-8: the replacement character
        }
    }
  }
  return out + "\"";
}

std::string JsonValue::dump(int indent) const {
  std::string out;
  dump_to(out, indent, 0);
  return out;
}

void JsonValue::dump_to(std::string& out, int indent, int depth) const {
  switch (kind_) {
    case Kind::null: out += "null"; return;
    case Kind::boolean: out += boolean_ ? "true" : "false"; return;
    case Kind::number: out += std::isfinite(number_) ? format_double(number_) : "null"; return;
    case Kind::integer: out += std::to_string(integer_); return;
    case Kind::string: out += json_quote(string_); return;
    case Kind::array:
    case Kind::object: break;
  }
  const bool is_object = kind_ == Kind::object;
  const char open = is_object ? '{' : '[';
  const char close = is_object ? '}' : ']';
  if (values_.empty()) {
    out += open;
    out += close;
    return;
  }
  bool all_scalars = !is_object;
  for (const auto& item : values_) all_scalars = all_scalars && item.size() == 0;
  const bool multiline = indent >= 0 && !all_scalars;
  const std::string inner(multiline ? static_cast<std::size_t>(indent * (depth + 1)) : 0, ' ');
  out += open;
  for (std::size_t i = 0; i < values_.size(); ++i) {
    if (i > 0) out += ',';
    if (multiline) {
      out += '\n';
      out += inner;
    } else if (i > 0 && indent >= 0) {
      out += ' ';
    }
    if (is_object) {
      out += json_quote(keys_[i]);
      out += indent >= 0 ? ": " : ":";
    }
    values_[i].dump_to(out, indent, depth + 1);
  }
  if (multiline) {
    out += '\n';
    out += std::string(static_cast<std::size_t>(indent * depth), ' ');
  }
  out += close;
}

}  // namespace fibrane::io
