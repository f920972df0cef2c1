// The joint map: which URDF joints become model joints, which are locked and at what angle. The
// grammar (docs/urdf.md) is read character by character, so that every error names its line and column.
#include "humandyn/urdf.hpp"
#include "text/decimal.hpp"
#include "text/file.hpp"
#include "text/shown.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace humandyn::urdf {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t'; }
// a name runs to the next blank, comment or `=`
bool ends_name(char c) { return is_blank(c) || c == '#' || c == '='; }

// One line being read: the text up to its comment, a position in it, and messages naming the column.
class LineReader {
 public:
  LineReader(std::string text, std::string where) : text_(std::move(text)), where_(std::move(where)) {}

  bool done() const { return pos_ == text_.size(); }
  char peek() const { return text_[pos_]; }
  void skip_blanks() {
    while (!done() && is_blank(peek())) ++pos_;
  }
  std::size_t pos() const { return pos_; }
  void advance() { ++pos_; }
  std::string rest() const { return text_.substr(pos_); }

  std::string name() {
    const std::size_t begin = pos_;
    while (!done() && !ends_name(peek())) ++pos_;
    return text_.substr(begin, pos_ - begin);
  }

  // number = [+|-] (digits [. digits*] | . digits) [(e|E) [+|-] digits]; finite
  double number() {
    const std::size_t begin = pos_;
    const std::size_t k = begin + text::decimal_prefix(std::string_view(text_).substr(begin));
    const bool ok = k > begin;
    std::size_t end = begin;
    while (end < text_.size() && !is_blank(text_[end])) ++end;
    const std::string word = text_.substr(begin, end - begin);
    if (word.empty()) fail(begin, "expected a number after '='");
    if (!ok || k != end) fail(begin, "'" + text::shown(word) + "' is not a number");
    double v = 0;  // (the grammar above admits no inf or nan; a subnormal reads, as in the CSV and BVH readers)
    if (text::read_double(word, v) != std::errc()) fail(begin, "'" + word + "'" + text::out_of_range(word));
    pos_ = end;
    return v;
  }

  // "source:line:column: what", the column counted in characters from 1
  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    std::size_t column = 1;
    for (std::size_t i = 0; i < at && i < text_.size(); ++i)
      if ((static_cast<unsigned char>(text_[i]) & 0xC0) != 0x80) ++column;  // UTF-8 continuation bytes do not count
    throw Error(where_ + ":" + std::to_string(column) + ": " + what);
  }

 private:
  std::string text_;
  std::string where_;
  std::size_t pos_ = 0;
};

}  // namespace

JointMap parse_joint_map(const std::string& text, const std::string& source) {
  JointMap map;
  map.source = source;
  // line by line: LF, CRLF or a lone CR (old Mac OS) ends one
  std::size_t next = 0;
  for (int number = 1; next < text.size(); ++number) {
    const std::size_t end = std::min(text.find_first_of("\r\n", next), text.size());
    std::string line = text.substr(next, end - next);
    next = end + (text.compare(end, 2, "\r\n") == 0 ? 2 : 1);
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte-order mark
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    LineReader in(line, source + ":" + std::to_string(number));
    in.skip_blanks();
    if (in.done()) continue;
    JointMapEntry e;
    e.line = number;
    const std::size_t name_at = in.pos();
    e.urdf_joint = in.name();
    if (e.urdf_joint.empty()) in.fail(name_at, "expected a URDF joint name before '='");
    in.skip_blanks();
    std::size_t model_at = name_at;
    if (!in.done() && in.peek() == '=') {  // urdf_joint = value
      in.advance();
      in.skip_blanks();
      const std::size_t value_at = in.pos();
      e.value = in.number();
      if (!(std::abs(e.value) <= 1e6))  // (as a URDF's origins: larger ones drown the import's tolerances)
        in.fail(value_at, "a lock value beyond 1e6 (rad or m) is refused, as the URDF's origin values are");
      e.locked = true;
    } else if (!in.done()) {  // urdf_joint model_name
      model_at = in.pos();
      e.model_name = in.name();
      in.skip_blanks();
      if (!in.done() && in.peek() == '=')
        in.fail(in.pos(),
                "'=' after a second name: `urdf_joint = value` locks a joint, `urdf_joint model_name` renames it");
    }
    in.skip_blanks();
    if (!in.done())
      in.fail(in.pos(),
              "unexpected '" + text::shown(in.rest()) + "' after " + (e.locked ? "the value" : "the model name"));
    if (!e.locked) {
      if (e.model_name.empty()) e.model_name = e.urdf_joint;
      if (const std::string fault = name_fault(e.model_name); !fault.empty())
        in.fail(model_at, "joint '" + text::shown(e.model_name) + "': " + fault + ", so no CSV column can name it");
    }
    map.entries.push_back(e);
  }
  return map;
}

JointMap read_joint_map(const std::string& path) {
  std::string content;
  if (const std::string fault = text::read_whole_file(path, content); !fault.empty())
    throw Error(text::shown(path) + ": " + fault);
  return parse_joint_map(content, text::shown(path));
}

}  // namespace humandyn::urdf
