// Joint names: the one rule for a name that heads CSV columns (q_<name>, tau_<name>, ...), applied
// wherever a joint name is read (a URDF, a joint map, a model file); and the looser one for the names of
// links and models.
// Header-only and internal, as shown.hpp.
#pragma once

#include "text/shown.hpp"

#include <string>
#include <string_view>

namespace humandyn::text {

namespace name_rule {

inline bool is_control(char32_t c) { return c < 0x20 || (c >= 0x7F && c <= 0x9F); }

inline bool is_invisible(char32_t c) {
  return c == 0xAD || (c >= 0x200B && c <= 0x200F) || c == 0x2028 || c == 0x2029 || (c >= 0x202A && c <= 0x202E) ||
         (c >= 0x2060 && c <= 0x2064) || c == 0xFEFF;
}

inline bool is_blank(char32_t c) { return c == ' ' || c == 0xA0; }

// U+FFFE and U+FFFF: no characters, which XML (a URDF) cannot carry
inline bool is_noncharacter(char32_t c) { return c == 0xFFFE || c == 0xFFFF; }

}  // namespace name_rule

/// Why `name` cannot be a joint's name, or "" when it can: non-empty UTF-8 without a comma, a double quote,
/// a control or an invisible character, neither starting nor ending with a blank (urdf.hpp gives the list).
inline std::string name_fault(const std::string& name) {
  using namespace name_rule;
  if (name.empty()) return "the name is empty";
  char32_t first = 0, last = 0;
  for (std::size_t i = 0; i < name.size();) {
    const CodePoint p = decode_utf8(std::string_view(name).substr(i));
    if (p.length == 0) return "the name is not UTF-8 (byte " + shown(name.substr(i, 1)) + ")";
    if (p.c == ',') return "the name holds a comma";
    if (p.c == '"') return "the name holds a double quote";
    if (is_control(p.c)) return "the name holds a control character, " + shown(name.substr(i, p.length));
    if (is_invisible(p.c)) return "the name holds an invisible character, " + shown(name.substr(i, p.length));
    if (is_noncharacter(p.c)) return "the name holds a noncharacter, " + shown(name.substr(i, p.length));
    if (i == 0) first = p.c;
    last = p.c;
    i += p.length;
  }
  if (is_blank(first)) return "the name starts with a blank";
  if (is_blank(last)) return "the name ends with a blank";
  return "";
}

/// Why `name` cannot name a link or a model, or "" when it can: non-empty UTF-8 without a control character
/// other than tab, line feed and carriage return, which XML carries, and without U+FFFE and U+FFFF (a link's name heads
/// no column: commas, quotes and blanks may stay; tables and messages show it by shown()'s rule). A byte that is not
/// UTF-8 would break a JSON document, another control character a URDF.
inline std::string label_fault(const std::string& name) {
  if (name.empty()) return "the name is empty";
  for (std::size_t i = 0; i < name.size();) {
    const CodePoint p = decode_utf8(std::string_view(name).substr(i));
    if (p.length == 0) return "the name is not UTF-8 (byte " + shown(name.substr(i, 1)) + ")";
    if (name_rule::is_control(p.c) && p.c != '\t' && p.c != '\n' && p.c != '\r')
      return "the name holds a control character, " + shown(name.substr(i, p.length));
    if (name_rule::is_noncharacter(p.c)) return "the name holds a noncharacter, " + shown(name.substr(i, p.length));
    i += p.length;
  }
  return "";
}

}  // namespace humandyn::text
