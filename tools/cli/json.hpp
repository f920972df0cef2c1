// A small JSON reader and writer for the command line's model files and configuration files.
//
// Reading is strict RFC 8259 (no comments, no trailing commas, no NaN, no repeated keys) and every
// value remembers where it stood, so that a caller checking the meaning of a file can still say
// "model.json: line 12, column 17: 'mass' must be a number". Objects keep their members in order.
// Numbers are doubles, written in the shortest form that reads back to the same double.
#pragma once

#include "cli/args.hpp"

#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace humandyn::cli::json {

class Value;
using Array = std::vector<Value>;
using Object = std::vector<std::pair<std::string, Value>>;

class Value {
 public:
  enum class Kind { Null, Bool, Number, String, Array, Object };

  Value() = default;  // null
  Value(std::nullptr_t) {}
  Value(bool b) : v_(b) {}
  Value(double x) : v_(x) {}
  Value(int x) : v_(double(x)) {}
  Value(const char* s) : v_(std::string(s)) {}
  Value(std::string s) : v_(std::move(s)) {}
  Value(Array a) : v_(std::move(a)) {}
  Value(Object o) : v_(std::move(o)) {}

  Kind kind() const { return Kind(v_.index()); }
  bool is_null() const { return kind() == Kind::Null; }
  bool is_number() const { return kind() == Kind::Number; }
  bool is_string() const { return kind() == Kind::String; }
  bool is_array() const { return kind() == Kind::Array; }
  bool is_object() const { return kind() == Kind::Object; }

  // The content, or InputError at this value's position naming `what` (e.g. "'mass'") and the
  // expected type.
  bool as_bool(std::string_view what = "value") const;
  double as_number(std::string_view what = "value") const;
  int as_int(std::string_view what = "value") const;  // a whole number that fits an int
  const std::string& as_string(std::string_view what = "value") const;
  const Array& as_array(std::string_view what = "value") const;
  const Object& as_object(std::string_view what = "value") const;

  // Object members: the value of `key` (nullptr / InputError naming the key when absent).
  const Value* find(std::string_view key) const;
  const Value& at(std::string_view key) const;
  // InputError for the first member whose key is not in `known` (catches typos in files).
  void reject_unknown_keys(const std::vector<std::string_view>& known) const;

  // Building: appends a member to an object (turning null into an empty object first).
  Value& set(std::string key, Value value);

  // "<source>: line L, column C: <message>" for this value (just the message for a built value).
  [[noreturn]] void fail(const std::string& message) const;
  std::string where() const;

 private:
  friend class Parser;
  std::variant<std::nullptr_t, bool, double, std::string, Array, Object> v_;
  std::shared_ptr<const std::string> source_;
  int line_ = 0, column_ = 0;
};

// Parses JSON text; `source` names it in messages. InputError with line and column on bad syntax.
Value parse(std::string_view text, const std::string& source);

// Reads and parses a file. InputError if it cannot be read or parsed.
Value read_file(const std::string& path);

// Indented JSON text with a final newline; short arrays and flat objects stay on one line.
// Throws std::invalid_argument for a non-finite number (JSON has none).
std::string write(const Value& value);

}  // namespace humandyn::cli::json
