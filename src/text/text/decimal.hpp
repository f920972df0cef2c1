// The one decimal-number grammar of the URDF pre-checks and the joint map:
//   [+|-] (digits [. digits*] | . digits) [(e|E) [+|-] digits]
// (no hexadecimal, inf or nan), and the one conversion of a number's text to a double, which the CSV,
// BVH and joint-map readers share. Header-only and internal, as shown.hpp.
#pragma once

#include <algorithm>
#include <charconv>
#include <cstddef>
#include <string>
#include <string_view>
#include <system_error>

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

/// Reads the whole of `s` as a double, by std::from_chars with a leading '+' allowed (not "+-").
/// \return std::errc() with `out` set (a subnormal reads as itself; `out` untouched otherwise); result_out_of_range
/// where the value
///         overflows or underflows to zero; invalid_argument where `s` is not one number (from_chars also
///         takes "inf", "nan" and hexadecimal without "0x": the callers' grammars decide on those)
inline std::errc read_double(std::string_view s, double& out) {
  if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc()) return ec;
  if (end != s.data() + s.size()) return std::errc::invalid_argument;
  out = value;  // (only on success: `out` is left as it was otherwise, as from_chars leaves it)
  return std::errc();
}

/// Why a decimal number read_double found out of range is: " is out of the range of a double: too large"
/// (its size overflows), or "...: too small, it would read as 0" (it underflows), from where its first
/// non-zero digit stands.
inline std::string out_of_range(std::string_view s) {
  const std::size_t e = s.find_first_of("eE");
  const std::string_view mantissa = s.substr(0, e);
  long long exponent = 0;  // (saturated: the digits of a huge exponent only need its sign)
  if (e != std::string_view::npos)
    for (std::size_t k = e + 1; k < s.size(); ++k)
      if (s[k] >= '0' && s[k] <= '9') exponent = std::min(exponent * 10 + (s[k] - '0'), 1000000000LL);
  if (e != std::string_view::npos && s.find('-', e) != std::string_view::npos) exponent = -exponent;
  // the power of ten of the first non-zero digit
  const std::size_t point = std::min(mantissa.find('.'), mantissa.size());
  const std::size_t first = mantissa.find_first_of("123456789");
  const auto ll = [](std::size_t n) { return static_cast<long long>(n); };
  const long long order = first == std::string_view::npos ? -1
                          : first < point                 ? ll(point - first) - 1
                                                          : -ll(first - point);
  return std::string(" is out of the range of a double: ") +
         (order + exponent >= 0 ? "too large" : "too small, it would read as 0");
}

}  // namespace humandyn::text
