// Joint names: the one rule for a name that heads CSV columns, and names shown with their invisible
// characters made visible.
#include "humandyn/urdf.hpp"

#include <cstdint>
#include <cstdio>

namespace humandyn::urdf {

namespace {

// One UTF-8 sequence at text[i]: its code point and length, or length 0 when the bytes there are not
// UTF-8 (a stray continuation byte, a truncated or overlong sequence, a surrogate, beyond U+10FFFF).
struct CodePoint {
  char32_t c = 0;
  std::size_t length = 0;
};

CodePoint decode(const std::string& text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b = byte(i);
  if (b < 0x80) return {b, 1};
  const std::size_t n = b >= 0xF0 && b <= 0xF4 ? 4 : b >= 0xE0 ? 3 : b >= 0xC2 && b <= 0xDF ? 2 : 0;
  if (n == 0 || i + n > text.size()) return {};
  char32_t c = b & (0x7F >> n);
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return {};
    c = (c << 6) | (byte(i + k) & 0x3F);
  }
  const char32_t least[] = {0, 0, 0x80, 0x800, 0x10000};
  if (c < least[n] || c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) return {};
  return {c, n};
}

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
    const CodePoint p = decode(name, i);
    if (p.length == 0) return "the name is not UTF-8 (byte " + shown(name.substr(i, 1)) + ")";
    if (p.c == ',') return "the name holds a comma";
    if (p.c == '"') return "the name holds a double quote";
    if (is_control(p.c)) return "the name holds a control character, " + shown(name.substr(i, p.length));
    if (is_invisible(p.c)) return "the name holds an invisible character, " + code(p.c);
    if (i == 0) first = p.c;
    last = p.c;
    i += p.length;
  }
  if (is_blank(first)) return "the name starts with a blank";
  if (is_blank(last)) return "the name ends with a blank";
  return "";
}

std::string shown(const std::string& text) {
  // the spaces of a leading or trailing run are the ones shown
  const std::size_t body_begin = text.find_first_not_of(' '), body_end = text.find_last_not_of(' ') + 1;
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    const CodePoint p = decode(text, i);
    if (p.length == 0) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "<0x%02X>", static_cast<unsigned char>(text[i]));
      out += buf;
      ++i;
      continue;
    }
    const bool at_end = body_begin == std::string::npos || i < body_begin || i >= body_end;
    if (p.c == '\t')
      out += "\\t";
    else if (p.c == '\n')
      out += "\\n";
    else if (p.c == '\r')
      out += "\\r";
    else if (p.c == ' ' && at_end)
      out += "\u2420";
    else if (is_control(p.c) || is_invisible(p.c) || p.c == 0xA0)
      out += code(p.c);
    else
      out.append(text, i, p.length);
    i += p.length;
  }
  return out;
}

}  // namespace humandyn::urdf
