// Joint names: the one rule for a name that heads CSV columns.
#include "humandyn/urdf.hpp"
#include "text/shown.hpp"

#include <cstdio>
#include <string_view>

namespace humandyn::urdf {

namespace {

bool is_control(char32_t c) { return c < 0x20 || (c >= 0x7F && c <= 0x9F); }

bool is_invisible(char32_t c) {
  return c == 0xAD || (c >= 0x200B && c <= 0x200F) || c == 0x2028 || c == 0x2029 || (c >= 0x202A && c <= 0x202E) ||
         (c >= 0x2060 && c <= 0x2064) || c == 0xFEFF;
}

bool is_blank(char32_t c) { return c == ' ' || c == 0xA0; }

std::string code(char32_t c) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "<U+%04X>", static_cast<unsigned>(c));
  return buf;
}

}  // namespace

std::string name_fault(const std::string& name) {
  if (name.empty()) return "the name is empty";
  char32_t first = 0, last = 0;
  for (std::size_t i = 0; i < name.size();) {
    const text::CodePoint p = text::decode_utf8(std::string_view(name).substr(i));
    if (p.length == 0) return "the name is not UTF-8 (byte " + text::shown(name.substr(i, 1)) + ")";
    if (p.c == ',') return "the name holds a comma";
    if (p.c == '"') return "the name holds a double quote";
    if (is_control(p.c)) return "the name holds a control character, " + text::shown(name.substr(i, p.length));
    if (is_invisible(p.c)) return "the name holds an invisible character, " + code(p.c);
    if (i == 0) first = p.c;
    last = p.c;
    i += p.length;
  }
  if (is_blank(first)) return "the name starts with a blank";
  if (is_blank(last)) return "the name ends with a blank";
  return "";
}

}  // namespace humandyn::urdf
