// What the BVH reader, writer and landmark map share: splitting text into lines, places in messages, numbers.
#pragma once

#include "humandyn/bvh.hpp"
#include "humandyn/model.hpp"
#include "text/decimal.hpp"
#include "text/names.hpp"
#include "text/shown.hpp"

#include <cmath>
#include <string>
#include <string_view>
#include <vector>

namespace humandyn::motion::detail {

inline bool is_blank(char c) { return c == ' ' || c == '\t'; }

// Where a joint name breaks the rule for names (UTF-8 without a control character: C0, DEL or C1, and
// not ending in '{', which the reader takes for the block's brace) and how ("has a control character"),
// or at == npos when it holds.
struct NameFault {
  std::size_t at = std::string_view::npos;  // byte offset in the name
  std::string how;
};
inline NameFault name_fault(std::string_view name) {
  if (name.ends_with('{')) return {name.size() - 1, "ends in '{'"};  // (first: `JOINT\tLeftLeg\t{` is this)
  for (std::size_t i = 0; i < name.size();) {
    const text::CodePoint p = text::decode_utf8(name.substr(i));
    if (p.length == 0) return {i, "is not UTF-8 (byte " + text::shown(name.substr(i, 1)) + ")"};
    if (text::name_rule::is_control(p.c)) return {i, "has a control character"};
    i += p.length;
  }
  return {};
}

// The text's lines without their ends (LF, CRLF, or a lone CR: old Mac OS), and without a leading UTF-8
// byte-order mark.
inline std::vector<std::string_view> split_lines(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  std::vector<std::string_view> lines;
  while (!text.empty()) {
    const std::size_t end = text.find_first_of("\r\n");
    lines.push_back(text.substr(0, end));
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + (text.substr(end, 2) == "\r\n" ? 2 : 1));
  }
  return lines;
}

// `s` without the blanks at either end.
inline std::string_view trimmed(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

// `text` for a message, what cannot be seen made visible (text/shown.hpp), cut after 40 bytes.
inline std::string shown(std::string_view text) {
  return humandyn::text::shown(text.substr(0, 40)) + (text.size() > 40 ? "..." : "");
}

// `text` shown in single quotes.
inline std::string quoted(std::string_view text) {
  std::string out(1, '\'');
  out += shown(text);
  out += '\'';
  return out;
}

// "source:line:column: what", the column of byte `at` of `line` counted in characters from 1.
[[noreturn]] inline void fail_at(const std::string& source, std::size_t line_index, std::string_view line,
                                 std::size_t at, const std::string& what) {
  std::size_t column = 1;
  for (std::size_t i = 0; i < at && i < line.size(); ++i)
    if ((static_cast<unsigned char>(line[i]) & 0xC0) != 0x80) ++column;  // UTF-8 continuation bytes do not count
  throw BvhError(source + ":" + std::to_string(line_index + 1) + ":" + std::to_string(column) + ": " + what);
}

// An error at the end of the text: on its last line, after the line's last character (line 1, column 1
// for an empty text).
[[noreturn]] inline void fail_at_end(const std::string& source, const std::vector<std::string_view>& lines,
                                     const std::string& what) {
  if (lines.empty()) fail_at(source, 0, {}, 0, what);
  fail_at(source, lines.size() - 1, lines.back(), lines.back().size(), what);
}

// Why `word` is not a finite decimal number ("" when it is one; then `value` holds it).
inline std::string number_fault(std::string_view word, double& value) {
  const std::errc ec = text::read_double(word, value);
  const std::string why = ec == std::errc::result_out_of_range ? text::out_of_range(word)
                          : ec != std::errc()                  ? " is not a number"
                          : !std::isfinite(value)              ? " is not a finite number"
                                                               : "";
  if (why.empty()) return {};
  std::string fault = quoted(word);
  fault += why;
  return fault;
}

// A double in the shortest form that reads back to the same value.
inline void append_number(std::string& out, double x) { out += exact_number(x); }

}  // namespace humandyn::motion::detail
