// JSON for the command line's files, on nlohmann::json (keys kept in the order written).
//
// Reading is strict RFC 8259 (no comments, no trailing commas, no NaN, no repeated keys, nesting at most
// 200 deep): a syntax error is an InputError "model.json: line 12, column 17: <what>". A value is then
// read through a Node, which knows its JSON path, so that an error in the meaning names it:
// "model.json: /joints/3/link/mass: must be a number, not a string".
// Writing: indented by two spaces, numbers in the shortest form that reads back to the same double, and
// a non-finite number (JSON has none) written as null, the one rule for every file we write.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace humandyn::cli::json {

using Json = nlohmann::ordered_json;

// Parses JSON text; `source` names it in messages. InputError with line and column on bad syntax.
Json parse(std::string_view text, const std::string& source);

// Reads and parses a file. InputError if it cannot be read or parsed.
Json read_file(const std::string& path);

// Indented JSON text with a final newline.
std::string write(const Json& value);

// A value of a parsed document and where it stands, for reading with clear errors (InputError
// "<source>: <path>: <message>").
class Node {
 public:
  Node(const Json& value, std::string source, std::string path = "")
      : value_(&value), source_(std::move(source)), path_(std::move(path)) {}

  const Json& value() const { return *value_; }
  const std::string& path() const { return path_; }
  [[noreturn]] void fail(const std::string& message) const;

  // The content, or an error naming the expected type.
  double number() const;
  int whole() const;  // a whole number that fits an int
  const std::string& string() const;
  std::size_t size() const;                  // of an array
  Node operator[](std::size_t index) const;  // of an array
  void expect_object() const;

  // Object members: the value of `key` (nullopt / an error naming the key when absent).
  std::optional<Node> find(const std::string& key) const;
  Node at(const std::string& key) const;
  // An error naming the first member whose key is not in `known` (catches typos in files).
  void reject_unknown_keys(const std::vector<std::string_view>& known) const;

 private:
  const Json* value_;
  std::string source_;
  std::string path_;  // a JSON pointer, "" for the document
};

}  // namespace humandyn::cli::json
