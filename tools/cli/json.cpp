#include "cli/json.hpp"

#include "cli/atomic_file.hpp"
#include "cli/errors.hpp"
#include "text/decimal.hpp"
#include "text/file.hpp"
#include "text/shown.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <limits>
#include <set>

namespace humandyn::cli::json {

namespace {

constexpr int max_depth = 200;

// "line L, column C" of the byte at `offset` (0-based) of `text`; LF, CRLF and a lone CR end a line.
std::string line_and_column(std::string_view text, std::size_t offset) {
  offset = std::min(offset, text.size());
  std::size_t line = 1, line_start = 0;
  for (std::size_t i = 0; i < offset; ++i)
    if (text[i] == '\n' || (text[i] == '\r' && !(i + 1 < text.size() && text[i + 1] == '\n'))) {
      ++line;
      line_start = i + 1;
    }
  return fmt::format("line {}, column {}", line, offset - line_start + 1);
}

// nlohmann's message without its "[json.exception...] parse error at line L, column C: " head.
std::string reason(const nlohmann::json::exception& e) {
  const std::string what = e.what();
  if (const std::size_t colon = what.find(": "); colon != std::string::npos) return what.substr(colon + 2);
  const std::size_t head = what.find("] ");
  return head == std::string::npos ? what : what.substr(head + 2);
}

const char* type_name(const Json& v) {
  switch (v.type()) {
    case Json::value_t::null:
      return "null";
    case Json::value_t::boolean:
      return "true or false";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float:
      return "a number";
    case Json::value_t::string:
      return "a string";
    case Json::value_t::array:
      return "an array";
    case Json::value_t::object:
      return "an object";
    default:
      return "binary data";
  }
}

// The offset of the first number literal outside the strings of `text` (a run of digits, signs, points and
// exponents) for which `wanted(literal)` holds, or text.size().
template <class F>
std::size_t find_number_where(std::string_view text, F&& wanted) {
  const auto in_number = [](char c) {
    return (c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.' || c == 'e' || c == 'E';
  };
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
      continue;
    }
    if (c == '"') in_string = true;
    if (c != '-' && !(c >= '0' && c <= '9')) continue;
    std::size_t end = i;
    while (end < text.size() && in_number(text[end])) ++end;
    if (wanted(text.substr(i, end - i))) return i;
    i = end - 1;
  }
  return text.size();
}

std::size_t find_number(std::string_view text, std::string_view literal) {
  return find_number_where(text, [&](std::string_view l) { return l == literal; });
}

// A key inside a JSON pointer: '~' and '/' escaped (RFC 6901).
std::string pointer_token(const std::string& key) {
  std::string out;
  for (const char c : key) out += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
  return out;
}

// A number literal a double holds only as 0 (1e-400), which the parser reads as 0 without a word: refused
// where it stands (one beyond a double's largest is the parser's own error).
void refuse_underflow(std::string_view text, const std::string& source) {
  std::string_view literal;
  const std::size_t at = find_number_where(text, [&](std::string_view l) {
    double value = 0;
    literal = l;
    return text::read_double(l, value) == std::errc::result_out_of_range;
  });
  if (at < text.size())
    throw InputError(
        fmt::format("{}: {}: '{}'{}", source, line_and_column(text, at), literal, text::out_of_range(literal)));
}

}  // namespace

Json parse(std::string_view text, const std::string& source) {
  // the parser's callback refuses repeated keys and deep nesting, naming the path of the object
  std::vector<std::set<std::string>> keys;  // the keys seen in each open object
  std::vector<std::string> path;            // the pointer of each open container
  std::string last_key;
  std::vector<std::size_t> index;  // the next element index of each open array (or npos)
  const auto child = [&] {
    if (path.empty()) return std::string();
    if (index.back() == std::string::npos) return path.back() + "/" + text::shown(pointer_token(last_key));
    return path.back() + "/" + std::to_string(index.back()++);
  };
  const auto callback = [&](int depth, nlohmann::json::parse_event_t event, Json& parsed) {
    using E = nlohmann::json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
        if (depth >= max_depth)
          throw InputError(fmt::format("{}: {}: nested deeper than {} levels", source, child(), max_depth));
        path.push_back(child());
        index.push_back(event == E::array_start ? 0 : std::string::npos);
        keys.emplace_back();
        break;
      case E::object_end:
      case E::array_end:
        path.pop_back();
        index.pop_back();
        keys.pop_back();
        break;
      case E::key:
        last_key = parsed.get<std::string>();
        if (!keys.back().insert(last_key).second)
          throw InputError(fmt::format("{}: {}: key '{}' repeated in an object", source,
                                       path.back().empty() ? "the top level" : path.back(), text::shown(last_key)));
        break;
      case E::value:
        if (!index.empty() && index.back() != std::string::npos && !parsed.is_structured()) ++index.back();
        break;
    }
    return true;
  };
  if (const std::string fault = text::utf16_fault(text); !fault.empty())
    throw InputError(source + ": line 1: " + fault);
  // (the parser takes a NUL byte for the end of its input, and would pass over whatever follows it)
  if (const std::size_t nul = text.find('\0'); nul != std::string_view::npos)
    throw InputError(fmt::format("{}: {}: a NUL byte, which JSON text cannot hold (\\u0000 inside a string)", source,
                                 line_and_column(text, nul)));
  try {
    Json parsed = Json::parse(text.begin(), text.end(), callback, true, false);
    refuse_underflow(text, source);
    return parsed;
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte: the 1-based offset of the byte where the parser stopped
    // (the text it last read shown as messages show cells: a byte that is not UTF-8 as <0xFF>)
    std::string why = reason(e);
    constexpr std::string_view last_read = "; last read: '";
    if (const std::size_t at = why.find(last_read); at != std::string::npos && why.ends_with('\''))
      why = why.substr(0, at + last_read.size()) +
            text::shown(std::string_view(why).substr(at + last_read.size(), why.size() - at - last_read.size() - 1)) +
            "'";
    throw InputError(fmt::format("{}: {}: {}", source, line_and_column(text, e.byte ? e.byte - 1 : 0), why));
  } catch (const nlohmann::json::exception& e) {
    // a number beyond a double's range ("number overflow parsing '1e400'"): where its literal stands,
    // and the entry it was to be
    const std::string why = reason(e);
    const std::size_t open = why.find('\''), close = why.rfind('\'');
    const std::size_t at = open < close ? find_number(text, why.substr(open + 1, close - open - 1)) : text.size();
    const std::string entry = child();
    throw InputError(fmt::format("{}: {}{}{}", source, at < text.size() ? line_and_column(text, at) + ": " : "",
                                 entry.empty() ? "" : entry + ": ", why));
  }
}

Json read_file(const std::string& path) { return parse(read_input_file(path), text::shown(path)); }

std::string write(const Json& value) { return value.dump(2) + '\n'; }

// ---- reading values --------------------------------------------------------------------------------

void Node::fail(const std::string& message) const {
  throw InputError(fmt::format("{}: {}: {}", source_, path_.empty() ? "the top level" : path_, message));
}

double Node::number() const {
  if (!value_->is_number()) fail(fmt::format("must be a number, not {}", type_name(*value_)));
  return value_->get<double>();
}

int Node::whole() const {
  if (!value_->is_number_integer() || *value_ < std::numeric_limits<int>::min() ||
      *value_ > std::numeric_limits<int>::max())
    fail(value_->is_number() ? fmt::format("must be a whole number, not {}", value_->dump())
                             : fmt::format("must be a whole number, not {}", type_name(*value_)));
  return value_->get<int>();
}

const std::string& Node::string() const {
  if (!value_->is_string()) fail(fmt::format("must be a string, not {}", type_name(*value_)));
  return value_->get_ref<const std::string&>();
}

std::size_t Node::size() const {
  if (!value_->is_array()) fail(fmt::format("must be an array, not {}", type_name(*value_)));
  return value_->size();
}

Node Node::operator[](std::size_t i) const { return Node((*value_)[i], source_, path_ + "/" + std::to_string(i)); }

void Node::expect_object() const {
  if (!value_->is_object()) fail(fmt::format("must be an object, not {}", type_name(*value_)));
}

std::optional<Node> Node::find(const std::string& key) const {
  expect_object();
  const auto it = value_->find(key);
  if (it == value_->end()) return std::nullopt;
  return Node(*it, source_, path_ + "/" + pointer_token(key));
}

Node Node::at(const std::string& key) const {
  auto node = find(key);
  if (!node) fail(fmt::format("missing key '{}'", key));
  return *node;
}

void Node::reject_unknown_keys(const std::vector<std::string_view>& known) const {
  expect_object();
  for (const auto& [key, v] : value_->items())
    if (std::find(known.begin(), known.end(), key) == known.end())
      fail(fmt::format("unknown key '{}' (expected: {})", text::shown(key), fmt::join(known, ", ")));
}

}  // namespace humandyn::cli::json
