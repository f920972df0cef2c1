// Text as error messages show it, so that what cannot be seen is seen: the one rule of the URDF importer,
// the BVH reader and writer and the command line (their messages put it between single quotes).
// Header-only and internal: installed with no component, and no installed header includes it.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace humandyn::text {

/// One UTF-8 sequence at the start of `s`: its code point and length in bytes, or length 0 when the bytes
/// there are not UTF-8 (a stray continuation byte, a truncated or overlong sequence, a surrogate, beyond
/// U+10FFFF).
struct CodePoint {
  char32_t c = 0;
  std::size_t length = 0;
};

inline CodePoint decode_utf8(std::string_view s) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char b = byte(0);
  if (b < 0x80) return {b, 1};
  const std::size_t n = b >= 0xF0 && b <= 0xF4 ? 4 : b >= 0xE0 && b <= 0xEF ? 3 : b >= 0xC2 && b <= 0xDF ? 2 : 0;
  if (n == 0 || n > s.size()) return {};
  char32_t c = b & (0x7F >> n);
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(k) & 0xC0) != 0x80) return {};
    c = (c << 6) | (byte(k) & 0x3F);
  }
  constexpr char32_t least[] = {0, 0, 0x80, 0x800, 0x10000};
  if (c < least[n] || c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) return {};
  return {c, n};
}

/// The offset of the first byte of `s` that is not UTF-8, or npos when `s` is UTF-8 throughout.
inline std::size_t first_non_utf8(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = decode_utf8(s.substr(i)).length;
    if (n == 0) return i;
    i += n;
  }
  return std::string_view::npos;
}

/// Characters that print as nothing or as a plain blank: controls, the byte-order mark, no-break and
/// typographic spaces, zero-width characters and direction marks; and U+FFFE and U+FFFF, no characters.
inline bool invisible(char32_t c) {
  return c < 0x20 || (c >= 0x7F && c <= 0xA0) || c == 0xAD || (c >= 0x2000 && c <= 0x200F) ||
         (c >= 0x2028 && c <= 0x202F) || (c >= 0x205F && c <= 0x206F) || c == 0x3000 || c == 0xFEFF ||
         (c >= 0xFFF9 && c <= 0xFFFB) || c == 0xFFFE || c == 0xFFFF;
}

/// `text` with what cannot be seen made visible: tab, line feed, carriage return and backslash as \t \n
/// \r \\, a space at either end as ␠, other invisible characters (above) as <U+XXXX>, and a byte that is not
/// UTF-8 as <0xXX>. E.g. a byte-order mark glued to "t" shows as <U+FEFF>t, "hip " as hip␠.
inline std::string shown(std::string_view text) {
  // the spaces of a leading or trailing run are the ones shown as ␠
  const std::size_t body_begin = text.find_first_not_of(' '), body_end = text.find_last_not_of(' ') + 1;
  std::string out;
  char code[16];
  for (std::size_t i = 0; i < text.size();) {
    const CodePoint p = decode_utf8(text.substr(i));
    if (p.length == 0) {
      std::snprintf(code, sizeof code, "<0x%02X>", static_cast<unsigned char>(text[i]));
      out += code;
      ++i;
      continue;
    }
    const bool at_end = body_begin == std::string_view::npos || i < body_begin || i >= body_end;
    if (p.c == '\t')
      out += "\\t";
    else if (p.c == '\n')
      out += "\\n";
    else if (p.c == '\r')
      out += "\\r";
    else if (p.c == '\\')
      out += "\\\\";
    else if (p.c == ' ' && at_end)
      out += "\u2420";
    else if (invisible(p.c)) {
      std::snprintf(code, sizeof code, "<U+%04X>", static_cast<std::uint32_t>(p.c));
      out += code;
    } else
      out.append(text, i, p.length);
    i += p.length;
  }
  return out;
}

}  // namespace humandyn::text
