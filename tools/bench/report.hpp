// Writing the bench's results: a minimal JSON emitter (objects and arrays written in order, numbers that
// read back to the same double, non-finite numbers as null) and CSV rows.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace humandyn::bench {

inline std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", c);
      out += b;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

inline std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// {"key": value, ...} from pre-rendered values, in order.
class JsonObject {
 public:
  JsonObject& raw(const std::string& key, const std::string& rendered) {
    items_.push_back(json_string(key) + ": " + rendered);
    return *this;
  }
  JsonObject& num(const std::string& key, double v) { return raw(key, json_number(v)); }
  JsonObject& str(const std::string& key, const std::string& v) { return raw(key, json_string(v)); }
  JsonObject& boolean(const std::string& key, bool v) { return raw(key, v ? "true" : "false"); }
  std::string render(const std::string& indent = "") const {
    if (items_.empty()) return "{}";
    std::string out = "{\n";
    for (std::size_t i = 0; i < items_.size(); ++i)
      out += indent + "  " + items_[i] + (i + 1 < items_.size() ? ",\n" : "\n");
    return out + indent + "}";
  }

 private:
  std::vector<std::string> items_;
};

inline std::string json_array(const std::vector<std::string>& rendered, const std::string& indent = "") {
  if (rendered.empty()) return "[]";
  std::string out = "[\n";
  for (std::size_t i = 0; i < rendered.size(); ++i)
    out += indent + "  " + rendered[i] + (i + 1 < rendered.size() ? ",\n" : "\n");
  return out + indent + "]";
}

// A CSV cell: quoted when it holds a comma or a quote.
inline std::string csv_cell(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

inline std::string csv_number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

}  // namespace humandyn::bench
