// The one decimal-number grammar of the URDF pre-checks and the joint map:
//   [+|-] (digits [. digits*] | . digits) [(e|E) [+|-] digits]
// (no hexadecimal, inf or nan). Header-only and internal, as shown.hpp.
#pragma once

#include <cstddef>
#include <string_view>

namespace humandyn::text {

/// The length of the decimal number at the start of `s` by the grammar above, or 0 if none stands there.
inline std::size_t decimal_prefix(std::string_view s) {
  std::size_t k = 0;
  const auto digits = [&] {
    const std::size_t from = k;
    while (k < s.size() && s[k] >= '0' && s[k] <= '9') ++k;
    return k > from;
  };
  if (k < s.size() && (s[k] == '+' || s[k] == '-')) ++k;
  bool ok = digits();
  if (k < s.size() && s[k] == '.') {
    ++k;
    ok = digits() || ok;
  }
  if (!ok) return 0;
  if (k < s.size() && (s[k] == 'e' || s[k] == 'E')) {
    const std::size_t mantissa = k;
    ++k;
    if (k < s.size() && (s[k] == '+' || s[k] == '-')) ++k;
    if (!digits()) return mantissa;  // (an exponent without digits is not part of the number)
  }
  return k;
}

/// Whether the whole of `s` is one decimal number.
inline bool is_decimal(std::string_view s) { return !s.empty() && decimal_prefix(s) == s.size(); }

}  // namespace humandyn::text
