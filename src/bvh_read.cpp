// The BVH reader: the hierarchy word by word, the motion line by line, every error with its line and column.
#include "bvh_text.hpp"
#include "text/file.hpp"

#include <algorithm>
#include <array>
#include <unordered_map>

HUMANDYN_COMPONENT_ABI_DEFINE(bvh)  // this build's Eigen alignment (humandyn/detail/component_abi.hpp)

namespace humandyn::motion {

using detail::is_blank;

std::string_view channel_name(Channel c) {
  static constexpr std::array<std::string_view, 6> names{"Xposition", "Yposition", "Zposition",
                                                         "Xrotation", "Yrotation", "Zrotation"};
  return names[static_cast<std::size_t>(c)];
}

int BvhClip::channel_count() const {
  int n = 0;
  for (const auto& j : joints) n += static_cast<int>(j.channels.size());
  return n;
}

int BvhClip::frame_count() const {
  const int n = channel_count();
  return n == 0 ? 0 : static_cast<int>(values.size() / static_cast<std::size_t>(n));
}

int BvhClip::find(std::string_view name) const {
  for (std::size_t i = 0; i < joints.size(); ++i)
    if (!joints[i].end_site && joints[i].name == name) return static_cast<int>(i);
  return -1;
}

namespace {

// The text as words separated by blanks and line ends, each with its place.
class Reader {
 public:
  Reader(std::string_view text, std::string source) : lines_(detail::split_lines(text)), source_(std::move(source)) {}

  // The next word, on this line or a later one ("" at the end of the text).
  std::string_view word() {
    skip_blanks_and_lines();
    return at_end() ? std::string_view() : word_on_line();
  }

  // The next word on the current line ("" at its end).
  std::string_view word_on_line() {
    const std::string_view line = lines_[line_];
    while (pos_ < line.size() && is_blank(line[pos_])) ++pos_;
    word_at_ = pos_;
    while (pos_ < line.size() && !is_blank(line[pos_])) ++pos_;
    return line.substr(word_at_, pos_ - word_at_);
  }

  // The next word, which must be `keyword` (on the current line if `same_line`); `expected` for the message.
  void expect(std::string_view keyword, const std::string& expected, bool same_line = false) {
    const std::string_view w = same_line ? word_on_line() : word();
    if (w != keyword) fail_here(w, "expected " + expected);
  }

  // A number on the current line.
  double number(const std::string& what) {
    const std::string_view w = word_on_line();
    if (w.empty()) fail_here(w, "expected " + what);
    double v = 0;
    if (const std::string fault = detail::number_fault(w, v); !fault.empty()) fail_word(fault + " (" + what + ")");
    return v;
  }

  // A count on the current line: decimal digits only, at most `max`.
  long count(const std::string& what, long max) {
    const std::string_view w = word_on_line();
    if (w.empty()) fail_here(w, "expected " + what);
    long n = 0;
    for (const char c : w) {
      if (c < '0' || c > '9') fail_word("expected " + what + " (a whole number), found " + detail::quoted(w));
      n = n * 10 + (c - '0');
      if (n > max) fail_word(what + " " + detail::quoted(w) + " is larger than " + std::to_string(max));
    }
    return n;
  }

  // The rest of the current line without the blanks at its ends (a joint's name).
  std::string_view rest_of_line() {
    const std::string_view line = at_end() ? std::string_view() : lines_[line_];
    while (pos_ < line.size() && is_blank(line[pos_])) ++pos_;
    word_at_ = pos_;
    const std::string_view rest = detail::trimmed(line.substr(pos_));
    pos_ = line.size();
    return rest;
  }

  // Nothing but blanks may follow on the current line.
  void expect_line_end(const std::string& after) {
    const std::string_view line = lines_[line_];
    while (pos_ < line.size() && is_blank(line[pos_])) ++pos_;
    if (pos_ < line.size()) {
      word_at_ = pos_;
      fail_word("unexpected " + detail::quoted(line.substr(pos_)) + " after " + after);
    }
  }

  bool at_end() const { return line_ >= lines_.size(); }
  int line_number() const { return static_cast<int>(line_) + 1; }
  std::size_t next_line() { return ++line_, pos_ = 0, line_; }
  const std::vector<std::string_view>& lines() const { return lines_; }
  const std::string& source() const { return source_; }

  // An error at the last word read.
  [[noreturn]] void fail_word(const std::string& what) const {
    detail::fail_at(source_, line_, at_end() ? std::string_view() : lines_[line_], word_at_, what);
  }
  // "expected ..., found 'w'" (or the end of the line or of the file) at the last word read.
  [[noreturn]] void fail_here(std::string_view w, const std::string& expected) const {
    if (at_end()) detail::fail_at_end(source_, lines_, expected + ", found the end of the file");
    fail_word(expected + ", found " + (w.empty() ? std::string("the end of the line") : detail::quoted(w)));
  }

 private:
  void skip_blanks_and_lines() {
    while (!at_end()) {
      const std::string_view line = lines_[line_];
      while (pos_ < line.size() && is_blank(line[pos_])) ++pos_;
      if (pos_ < line.size()) return;
      next_line();
    }
  }

  std::vector<std::string_view> lines_;
  std::string source_;
  std::size_t line_ = 0, pos_ = 0, word_at_ = 0;
};

std::optional<Channel> channel_named(std::string_view w) {
  for (int c = 0; c < 6; ++c)
    if (channel_name(static_cast<Channel>(c)) == w) return static_cast<Channel>(c);
  return std::nullopt;
}

// The hierarchy: ROOT blocks, each a tree of JOINT and End Site blocks, read with a stack of open braces.
void read_hierarchy(Reader& in, BvhClip& clip) {
  std::unordered_map<std::string, int> lines_of_names;
  std::vector<int> open;  // joints whose '{' is not yet closed
  // a ROOT's or JOINT's name, '{', OFFSET and CHANNELS
  const auto joint = [&](std::string_view keyword, int parent) {
    BvhJoint j;
    j.parent = parent;
    j.line = in.line_number();
    const std::string_view name = in.rest_of_line();
    if (name.empty() || name == "{")
      in.fail_word("expected the name of the " + std::string(keyword) + " on its line" +
                   (name.empty() ? "" : ", before its '{'"));
    // (`JOINT LeftLeg {`: the name is the rest of the line, brace and all)
    if (const auto fault = detail::name_fault(name); fault.at != std::string_view::npos)
      in.fail_word("joint name " + detail::quoted(name) + " " + fault.how +
                   (name.ends_with('{') ? ": the name stands alone on its line, the '{' on the next" : ""));
    j.name = name;
    if (const auto [it, fresh] = lines_of_names.emplace(j.name, j.line); !fresh)
      in.fail_word("duplicate joint name " + detail::quoted(name) + " (first on line " + std::to_string(it->second) +
                   ")");
    in.expect("{", "'{' after " + std::string(keyword) + " " + detail::shown(name));
    in.expect("OFFSET", "OFFSET in joint " + detail::quoted(name));
    for (int k = 0; k < 3; ++k) j.offset[k] = in.number("OFFSET value " + std::to_string(k + 1) + " of 3");
    in.expect("CHANNELS", "CHANNELS in joint " + detail::quoted(name));
    const long n = in.count("the number of channels", 6);
    for (long k = 0; k < n; ++k) {
      const std::string_view w = in.word_on_line();
      const auto c = channel_named(w);
      if (!c)
        in.fail_here(w, "expected channel " + std::to_string(k + 1) + " of " + std::to_string(n) +
                            " (Xposition, Yposition, Zposition, Xrotation, Yrotation or Zrotation)");
      for (const Channel seen : j.channels)
        if (seen == *c) in.fail_word("channel " + std::string(w) + " listed twice in joint '" + j.name + "'");
      j.channels.push_back(*c);
    }
    open.push_back(static_cast<int>(clip.joints.size()));
    clip.joints.push_back(std::move(j));
  };

  in.expect("HIERARCHY", "HIERARCHY at the start of the file");
  std::string_view w = in.word();
  if (w != "ROOT") in.fail_here(w, "expected ROOT");
  while (w == "ROOT") {
    joint("ROOT", -1);
    while (!open.empty()) {
      w = in.word();
      if (w == "JOINT") {
        joint("JOINT", open.back());
      } else if (w == "End") {
        BvhJoint e;
        e.parent = open.back();
        e.end_site = true;
        e.line = in.line_number();
        in.expect("Site", "'Site' after 'End'");
        in.expect("{", "'{' after End Site");
        in.expect("OFFSET", "OFFSET in the End Site");
        for (int k = 0; k < 3; ++k) e.offset[k] = in.number("OFFSET value " + std::to_string(k + 1) + " of 3");
        in.expect("}", "'}' closing the End Site (an End Site has only an OFFSET)");
        clip.joints.push_back(std::move(e));
      } else if (w == "}") {
        open.pop_back();
      } else if (channel_named(w)) {
        in.fail_word("channel " + std::string(w) + " beyond the count given after CHANNELS in joint '" +
                     clip.joints[static_cast<std::size_t>(open.back())].name + "'");
      } else {
        in.fail_here(w, "expected JOINT, End Site or '}' in joint '" +
                            clip.joints[static_cast<std::size_t>(open.back())].name + "'");
      }
    }
    w = in.word();
  }
  if (w != "MOTION") in.fail_here(w, "expected ROOT or MOTION after the hierarchy");
  if (clip.channel_count() == 0) in.fail_word("the hierarchy has no channels, so the frames hold nothing");
}

// MOTION's header, then one line of values per frame.
void read_motion(Reader& in, BvhClip& clip) {
  in.expect_line_end("MOTION");
  in.expect("Frames:", "'Frames:' after MOTION");
  const long frames = in.count("the number of frames", 100'000'000);
  in.expect_line_end("the number of frames");
  in.expect("Frame", "'Frame Time:' after 'Frames:'");
  in.expect("Time:", "'Time:' after 'Frame'", true);
  clip.frame_time = in.number("the frame time in seconds");
  if (clip.frame_time <= 0) in.fail_word("the frame time must be positive");
  in.expect_line_end("the frame time");

  const auto& lines = in.lines();
  const std::size_t channels = static_cast<std::size_t>(clip.channel_count());
  const std::size_t first = in.next_line();
  clip.values.reserve(
      std::min<std::size_t>(static_cast<std::size_t>(frames), lines.size() - std::min(first, lines.size())) * channels);
  for (std::size_t f = 0; f < static_cast<std::size_t>(frames); ++f) {
    const std::size_t index = first + f;
    if (index >= lines.size())
      detail::fail_at_end(in.source(), lines,
                          "the file ends after " + std::to_string(f) + " of the " + std::to_string(frames) +
                              " frames that 'Frames:' announces");
    const std::string_view line = lines[index];
    std::size_t pos = 0, n = 0;
    while (true) {
      while (pos < line.size() && is_blank(line[pos])) ++pos;
      if (pos == line.size()) break;
      const std::size_t begin = pos;
      while (pos < line.size() && !is_blank(line[pos])) ++pos;
      if (n == channels)
        detail::fail_at(in.source(), index, line, begin,
                        "frame " + std::to_string(f + 1) + " has more than the hierarchy's " +
                            std::to_string(channels) + " channel values");
      double v = 0;
      if (const std::string fault = detail::number_fault(line.substr(begin, pos - begin), v); !fault.empty())
        detail::fail_at(in.source(), index, line, begin,
                        fault + " (frame " + std::to_string(f + 1) + ", value " + std::to_string(n + 1) + ")");
      clip.values.push_back(v);
      ++n;
    }
    if (n < channels)
      detail::fail_at(in.source(), index, line, line.size(),
                      "frame " + std::to_string(f + 1) + " has " + std::to_string(n) + " values, the hierarchy " +
                          std::to_string(channels) + " channels");
  }
  for (std::size_t index = first + static_cast<std::size_t>(frames); index < lines.size(); ++index)
    if (!detail::trimmed(lines[index]).empty())
      detail::fail_at(in.source(), index, lines[index], 0,
                      "a motion line beyond the " + std::to_string(frames) + " frames that 'Frames:' announces");
}

}  // namespace

BvhClip parse_bvh(std::string_view text, const std::string& source) {
  BvhClip clip;
  clip.source = source;
  Reader in(text, source);
  read_hierarchy(in, clip);
  read_motion(in, clip);
  return clip;
}

BvhClip read_bvh_file(const std::string& path) {
  std::string content;
  if (const std::string fault = text::read_whole_file(path, content); !fault.empty())
    throw BvhError(text::shown(path) + ": " + fault);
  return parse_bvh(content, text::shown(path));
}

}  // namespace humandyn::motion
