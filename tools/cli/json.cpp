#include "cli/json.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace humandyn::cli::json {

namespace {

const char* kind_name(Value::Kind k) {
  switch (k) {
    case Value::Kind::Null: return "null";
    case Value::Kind::Bool: return "true or false";
    case Value::Kind::Number: return "a number";
    case Value::Kind::String: return "a string";
    case Value::Kind::Array: return "an array";
    case Value::Kind::Object: return "an object";
  }
  return "?";
}

std::string number_text(double x) {
  if (!std::isfinite(x)) throw std::invalid_argument("JSON cannot hold the non-finite number " + std::to_string(x));
  char buf[64];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);  // shortest exact round trip
  return std::string(buf, end);
}

}  // namespace

// ---- the value -------------------------------------------------------------------------------------

std::string Value::where() const {
  if (!source_) return {};
  return *source_ + ": line " + std::to_string(line_) + ", column " + std::to_string(column_);
}

void Value::fail(const std::string& message) const {
  const std::string w = where();
  throw InputError(w.empty() ? message : w + ": " + message);
}

#define HUMANDYN_JSON_EXPECT(kind_enum, what)                                                              \
  if (kind() != kind_enum)                                                                                 \
    fail(std::string(what) + " must be " + kind_name(kind_enum) + ", not " + kind_name(kind()))

bool Value::as_bool(std::string_view what) const {
  HUMANDYN_JSON_EXPECT(Kind::Bool, what);
  return std::get<bool>(v_);
}

double Value::as_number(std::string_view what) const {
  HUMANDYN_JSON_EXPECT(Kind::Number, what);
  return std::get<double>(v_);
}

int Value::as_int(std::string_view what) const {
  const double x = as_number(what);
  if (x != std::floor(x) || x < std::numeric_limits<int>::min() || x > std::numeric_limits<int>::max())
    fail(std::string(what) + " must be a whole number, not " + number_text(x));
  return int(x);
}

const std::string& Value::as_string(std::string_view what) const {
  HUMANDYN_JSON_EXPECT(Kind::String, what);
  return std::get<std::string>(v_);
}

const Array& Value::as_array(std::string_view what) const {
  HUMANDYN_JSON_EXPECT(Kind::Array, what);
  return std::get<Array>(v_);
}

const Object& Value::as_object(std::string_view what) const {
  HUMANDYN_JSON_EXPECT(Kind::Object, what);
  return std::get<Object>(v_);
}

#undef HUMANDYN_JSON_EXPECT

const Value* Value::find(std::string_view key) const {
  for (const auto& [k, v] : as_object())
    if (k == key) return &v;
  return nullptr;
}

const Value& Value::at(std::string_view key) const {
  const Value* v = find(key);
  if (!v) fail("missing key '" + std::string(key) + "'");
  return *v;
}

void Value::reject_unknown_keys(const std::vector<std::string_view>& known) const {
  for (const auto& [k, v] : as_object()) {
    bool ok = false;
    for (const auto& name : known) ok = ok || name == k;
    if (!ok) {
      std::string list;
      for (const auto& name : known) list += (list.empty() ? "" : ", ") + std::string(name);
      v.fail("unknown key '" + k + "' (expected: " + list + ")");
    }
  }
}

Value& Value::set(std::string key, Value value) {
  if (is_null()) v_ = Object{};
  auto& members = std::get<Object>(v_);
  members.emplace_back(std::move(key), std::move(value));
  return members.back().second;
}

// ---- the reader ------------------------------------------------------------------------------------

class Parser {
 public:
  Parser(std::string_view text, const std::string& source)
      : text_(text), source_(std::make_shared<const std::string>(source)) {}

  Value document() {
    skip_space();
    if (pos_ >= text_.size()) error("empty document: expected a JSON value");
    Value v = value(0);
    skip_space();
    if (pos_ < text_.size()) error("unexpected text after the JSON value");
    return v;
  }

 private:
  static constexpr int max_depth = 200;

  [[noreturn]] void error_at(int line, int column, const std::string& message) const {
    throw InputError(*source_ + ": line " + std::to_string(line) + ", column " + std::to_string(column) + ": " +
                     message);
  }
  [[noreturn]] void error(const std::string& message) const { error_at(line_, column(), message); }
  int column() const { return int(pos_ - line_start_) + 1; }

  void skip_space() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        ++line_;
        line_start_ = ++pos_;
      } else if (c == ' ' || c == '\t' || c == '\r') {
        ++pos_;
      } else {
        break;
      }
    }
  }

  Value located(Value v, int line, int column) const {
    v.source_ = source_;
    v.line_ = line;
    v.column_ = column;
    return v;
  }

  Value value(int depth) {
    if (depth > max_depth) error("nested deeper than " + std::to_string(max_depth) + " levels");
    if (pos_ >= text_.size()) error("unexpected end of the document: expected a value");
    const int line = line_, col = column();
    const char c = text_[pos_];
    if (c == '{') return located(object(depth), line, col);
    if (c == '[') return located(array(depth), line, col);
    if (c == '"') return located(Value(string()), line, col);
    if (c == '-' || (c >= '0' && c <= '9')) return located(Value(number()), line, col);
    if (literal("true")) return located(Value(true), line, col);
    if (literal("false")) return located(Value(false), line, col);
    if (literal("null")) return located(Value(), line, col);
    error(std::string("unexpected character '") + c + "': expected a value");
  }

  bool literal(std::string_view word) {
    if (text_.substr(pos_, word.size()) != word) return false;
    pos_ += word.size();
    return true;
  }

  Object object(int depth) {
    Object members;
    ++pos_;  // {
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == '}') {
      ++pos_;
      return members;
    }
    for (;;) {
      skip_space();
      if (pos_ >= text_.size() || text_[pos_] != '"') error("expected a member name in double quotes");
      const int key_line = line_, key_col = column();
      std::string key = string();
      for (const auto& [k, v] : members)
        if (k == key) error_at(key_line, key_col, "key '" + key + "' repeated in an object");
      skip_space();
      if (pos_ >= text_.size() || text_[pos_] != ':') error("expected ':' after the member name");
      ++pos_;
      skip_space();
      Value v = value(depth + 1);
      members.emplace_back(std::move(key), std::move(v));
      skip_space();
      if (pos_ < text_.size() && text_[pos_] == ',') {
        ++pos_;
        continue;
      }
      if (pos_ < text_.size() && text_[pos_] == '}') {
        ++pos_;
        return members;
      }
      error("expected ',' or '}' after an object member");
    }
  }

  Array array(int depth) {
    Array items;
    ++pos_;  // [
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == ']') {
      ++pos_;
      return items;
    }
    for (;;) {
      skip_space();
      items.push_back(value(depth + 1));
      skip_space();
      if (pos_ < text_.size() && text_[pos_] == ',') {
        ++pos_;
        continue;
      }
      if (pos_ < text_.size() && text_[pos_] == ']') {
        ++pos_;
        return items;
      }
      error("expected ',' or ']' after an array element");
    }
  }

  // RFC 8259 number grammar, then the exact conversion of from_chars.
  double number() {
    const std::size_t start = pos_;
    const auto digits = [&] {
      const std::size_t from = pos_;
      while (pos_ < text_.size() && text_[pos_] >= '0' && text_[pos_] <= '9') ++pos_;
      return pos_ > from;
    };
    if (text_[pos_] == '-') ++pos_;
    if (pos_ < text_.size() && text_[pos_] == '0') {
      ++pos_;
    } else if (!digits()) {
      error("malformed number: expected a digit");
    }
    if (pos_ < text_.size() && text_[pos_] == '.') {
      ++pos_;
      if (!digits()) error("malformed number: expected a digit after '.'");
    }
    if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
      ++pos_;
      if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
      if (!digits()) error("malformed number: expected a digit in the exponent");
    }
    double x = 0;
    const auto [end, ec] = std::from_chars(text_.data() + start, text_.data() + pos_, x);
    if (ec == std::errc::result_out_of_range || !std::isfinite(x)) {
      pos_ = start;
      error("number " + std::string(text_.substr(start, std::size_t(end - text_.data()) - start)) +
            " is out of the range of a double");
    }
    return x;
  }

  unsigned hex4() {
    if (pos_ + 4 > text_.size()) error("truncated \\u escape");
    unsigned u = 0;
    for (int i = 0; i < 4; ++i) {
      const char h = text_[pos_++];
      u <<= 4;
      if (h >= '0' && h <= '9') u |= unsigned(h - '0');
      else if (h >= 'a' && h <= 'f') u |= unsigned(h - 'a' + 10);
      else if (h >= 'A' && h <= 'F') u |= unsigned(h - 'A' + 10);
      else error("bad hexadecimal digit in a \\u escape");
    }
    return u;
  }

  static void append_utf8(std::string& out, unsigned cp) {
    if (cp < 0x80) {
      out += char(cp);
    } else if (cp < 0x800) {
      out += char(0xC0 | (cp >> 6));
      out += char(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      out += char(0xE0 | (cp >> 12));
      out += char(0x80 | ((cp >> 6) & 0x3F));
      out += char(0x80 | (cp & 0x3F));
    } else {
      out += char(0xF0 | (cp >> 18));
      out += char(0x80 | ((cp >> 12) & 0x3F));
      out += char(0x80 | ((cp >> 6) & 0x3F));
      out += char(0x80 | (cp & 0x3F));
    }
  }

  std::string string() {
    std::string out;
    ++pos_;  // opening quote
    for (;;) {
      if (pos_ >= text_.size()) error("unterminated string");
      const char c = text_[pos_++];
      if (c == '"') return out;
      if (static_cast<unsigned char>(c) < 0x20) {
        --pos_;
        error("control character in a string (write it as an escape)");
      }
      if (c != '\\') {
        out += c;
        continue;
      }
      if (pos_ >= text_.size()) error("unterminated string");
      const char e = text_[pos_++];
      switch (e) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
          unsigned cp = hex4();
          if (cp >= 0xD800 && cp <= 0xDBFF) {  // a surrogate pair
            if (text_.substr(pos_, 2) != "\\u") error("unpaired surrogate in a \\u escape");
            pos_ += 2;
            const unsigned low = hex4();
            if (low < 0xDC00 || low > 0xDFFF) error("unpaired surrogate in a \\u escape");
            cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
          } else if (cp >= 0xDC00 && cp <= 0xDFFF) {
            error("unpaired surrogate in a \\u escape");
          }
          append_utf8(out, cp);
          break;
        }
        default:
          --pos_;
          error(std::string("unknown escape '\\") + e + "' in a string");
      }
    }
  }

  std::string_view text_;
  std::shared_ptr<const std::string> source_;
  std::size_t pos_ = 0, line_start_ = 0;
  int line_ = 1;
};

Value parse(std::string_view text, const std::string& source) { return Parser(text, source).document(); }

Value read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path + ": cannot read");
  return parse(text.str(), path);
}

// ---- the writer ------------------------------------------------------------------------------------

namespace {

void write_string(std::string& out, const std::string& s) {
  out += '"';
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(static_cast<unsigned char>(c)));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  out += '"';
}

void write_compact(std::string& out, const Value& v) {
  switch (v.kind()) {
    case Value::Kind::Null: out += "null"; break;
    case Value::Kind::Bool: out += v.as_bool() ? "true" : "false"; break;
    case Value::Kind::Number: out += number_text(v.as_number()); break;
    case Value::Kind::String: write_string(out, v.as_string()); break;
    case Value::Kind::Array: {
      out += '[';
      bool first = true;
      for (const auto& item : v.as_array()) {
        out += first ? "" : ", ";
        first = false;
        write_compact(out, item);
      }
      out += ']';
      break;
    }
    case Value::Kind::Object: {
      out += '{';
      bool first = true;
      for (const auto& [k, item] : v.as_object()) {
        out += first ? "" : ", ";
        first = false;
        write_string(out, k);
        out += ": ";
        write_compact(out, item);
      }
      out += '}';
      break;
    }
  }
}

// Small enough to read on one line: no object below the top level, no array nested twice.
bool flat(const Value& v, int level = 0) {
  if (v.is_object()) {
    if (level > 0) return false;
    for (const auto& [k, item] : v.as_object())
      if (!flat(item, level + 1)) return false;
    return true;
  }
  if (v.is_array()) {
    if (level > 1) return false;
    for (const auto& item : v.as_array())
      if (!flat(item, level + 1)) return false;
    return true;
  }
  return true;
}

void write_pretty(std::string& out, const Value& v, int indent) {
  constexpr std::size_t line_width = 110;
  if (!v.is_array() && !v.is_object()) {
    write_compact(out, v);
    return;
  }
  if (flat(v)) {
    std::string one_line;
    write_compact(one_line, v);
    if (one_line.size() + std::size_t(indent) <= line_width) {
      out += one_line;
      return;
    }
  }
  const std::string pad(std::size_t(indent + 2), ' ');
  if (v.is_array()) {
    if (v.as_array().empty()) {
      out += "[]";
      return;
    }
    out += "[\n";
    bool first = true;
    for (const auto& item : v.as_array()) {
      out += first ? "" : ",\n";
      first = false;
      out += pad;
      write_pretty(out, item, indent + 2);
    }
    out += '\n' + std::string(std::size_t(indent), ' ') + ']';
  } else {
    if (v.as_object().empty()) {
      out += "{}";
      return;
    }
    out += "{\n";
    bool first = true;
    for (const auto& [k, item] : v.as_object()) {
      out += first ? "" : ",\n";
      first = false;
      out += pad;
      write_string(out, k);
      out += ": ";
      write_pretty(out, item, indent + 2);
    }
    out += '\n' + std::string(std::size_t(indent), ' ') + '}';
  }
}

}  // namespace

std::string write(const Value& value) {
  std::string out;
  write_pretty(out, value, 0);
  out += '\n';
  return out;
}

}  // namespace humandyn::cli::json
