#pragma once
// A tiny JSON value builder and serializer for summary.json and `fibrane law` output. Objects keep
// their insertion order (readable output, stable diffs). Numbers are written with the shortest text
// that reads back to the identical double; JSON has no NaN/Infinity, so non-finite numbers become null.
#include <concepts>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

namespace fibrane::io {

class JsonValue {
 public:
  enum class Kind { null, boolean, number, integer, string, array, object };

  JsonValue() = default;  // null
  JsonValue(std::nullptr_t) {}
  JsonValue(bool value) : kind_(Kind::boolean), boolean_(value) {}
  JsonValue(double value) : kind_(Kind::number), number_(value) {}
  template <std::integral T>
    requires(!std::same_as<T, bool>)
  JsonValue(T value) : kind_(Kind::integer), integer_(static_cast<std::int64_t>(value)) {}
  JsonValue(const char* text) : kind_(Kind::string), string_(text) {}
  JsonValue(std::string text) : kind_(Kind::string), string_(std::move(text)) {}
  JsonValue(const std::vector<double>& numbers);  // array of numbers

  static JsonValue array(std::initializer_list<JsonValue> items = {});
  static JsonValue object();

  Kind kind() const { return kind_; }

  // Objects: inserts (or replaces) a member, returns *this for chaining. A null value becomes an object.
  JsonValue& set(const std::string& key, JsonValue value);
  // Objects: the member `key`, inserted as null if absent. A null value becomes an object.
  JsonValue& operator[](const std::string& key);
  // Arrays: appends. A null value becomes an array.
  JsonValue& push_back(JsonValue value);
  std::size_t size() const;  // members or items; 0 for scalars
  // Objects: the members in order (name, value).
  std::vector<std::pair<std::string, JsonValue>> members() const;

  // indent < 0: compact single line. Otherwise pretty-printed; arrays of scalars stay on one line.
  std::string dump(int indent = 2) const;

 private:
  void become(Kind kind);
  void dump_to(std::string& out, int indent, int depth) const;

  Kind kind_ = Kind::null;
  bool boolean_ = false;
  double number_ = 0.0;
  std::int64_t integer_ = 0;
  std::string string_;
  std::vector<std::string> keys_;   // object member names, parallel to values_
  std::vector<JsonValue> values_;   // object member values or array items
};

// JSON string literal with quotes and escapes (", \, control characters); valid UTF-8 passes through,
// each byte of an invalid sequence becomes \ufffd (the replacement character), so the output is valid JSON.
std::string json_quote(const std::string& text);

}  // namespace fibrane::io
