#include "cli/csv.hpp"
#include "cli/atomic_file.hpp"
#include "text/decimal.hpp"
#include "text/file.hpp"
#include "text/shown.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <iterator>
#include <set>
#include <sstream>
#include <string_view>
#include <unordered_map>

namespace humandyn::cli {

namespace {

bool blank(char c) { return c == ' ' || c == '\t'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

// "<source>: line L, column C 'name': message" (the name when the header gives one)
std::string located(const std::string& source, int line, int column, std::string_view name, std::string_view message) {
  if (column <= 0) return fmt::format("{}: line {}: {}", source, line, message);
  if (name.empty()) return fmt::format("{}: line {}, column {}: {}", source, line, column, message);
  return fmt::format("{}: line {}, column {} '{}': {}", source, line, column, text::shown(name), message);
}

[[noreturn]] void fail(const std::string& source, int line, int column, std::string_view name,
                       std::string_view message) {
  throw InputError(located(source, line, column, name, message));
}

// Splits CSV text into records (RFC 4180): cells separated by commas, records by \n, \r\n or a lone \r; a cell
// in double quotes may hold commas, line breaks and doubled quotes. Blanks around a cell are padding,
// not content; a quoted cell keeps the blanks inside its quotes.
class RecordReader {
 public:
  RecordReader(std::string_view text, const std::string& source) : text_(text), source_(source) {}

  // The next record that is not a blank line, into `cells`, and the line it starts on; false at the end.
  bool next(std::vector<std::string>& cells, int& line) {
    while (pos_ < text_.size()) {
      line = line_;
      cells.clear();
      bool quoted_any = false;
      for (;;) {
        const int column = int(cells.size()) + 1;
        while (pos_ < text_.size() && blank(text_[pos_])) ++pos_;
        std::string& cell = cells.emplace_back();
        if (pos_ < text_.size() && text_[pos_] == '"') {
          read_quoted(cell, column);
          quoted_any = true;
        } else {
          read_plain(cell, column);
        }
        if (pos_ < text_.size() && text_[pos_] == ',') {
          ++pos_;
          continue;
        }
        // the end of the record: \n, \r\n, a lone \r (old Mac OS line ends) or the end of the text
        skip_line_end();
        break;
      }
      if (cells.size() > 1 || quoted_any || !cells.front().empty()) return true;
    }
    return false;
  }

 private:
  // An unquoted cell, up to the comma or line end that closes it, without its padding.
  void read_plain(std::string& cell, int column) {
    const std::size_t end = std::min(text_.find_first_of(",\r\n", pos_), text_.size());
    std::string_view raw = text_.substr(pos_, end - pos_);
    if (raw.find('"') != std::string_view::npos)
      fail(source_, line_, column, {},
           "a quote inside an unquoted cell (quote the whole cell and write a quote in it twice: \"a\"\"b\")");
    cell.assign(trim(raw));
    pos_ = end;
  }

  // A quoted cell from its opening quote; "" stands for one quote; only padding may follow the closing one.
  void read_quoted(std::string& cell, int column) {
    const int opened = line_;
    ++pos_;
    for (;;) {
      if (pos_ >= text_.size()) fail(source_, opened, column, {}, "the quote that opens this cell is never closed");
      const char c = text_[pos_++];
      if (c == '"') {
        if (pos_ < text_.size() && text_[pos_] == '"') {
          cell += '"';
          ++pos_;
          continue;
        }
        break;
      }
      if (c == '\n' || (c == '\r' && !(pos_ < text_.size() && text_[pos_] == '\n'))) ++line_;
      cell += c;
    }
    while (pos_ < text_.size() && blank(text_[pos_])) ++pos_;
    const std::string_view rest = text_.substr(pos_);
    if (!(rest.empty() || rest.front() == ',' || rest.front() == '\n' || rest.front() == '\r'))
      fail(source_, line_, column, {},
           fmt::format("'{}' after the closing quote (a quote inside a quoted cell is written twice: \"\")",
                       text::shown(rest.substr(0, std::min(rest.find_first_of(",\r\n"), rest.size())))));
  }

  // Past the line end at pos_ (\n, \r\n or \r), if any.
  void skip_line_end() {
    if (pos_ >= text_.size()) return;
    if (text_[pos_++] == '\r' && pos_ < text_.size() && text_[pos_] == '\n') ++pos_;
    ++line_;
  }

  std::string_view text_;
  const std::string& source_;
  std::size_t pos_ = 0;
  int line_ = 1;
};

}  // namespace

bool parse_number(std::string_view cell, double& out, std::string& why) {
  if (cell.empty()) {
    why = "empty cell, expected a number";
    return false;
  }
  const std::errc ec = text::read_double(cell, out);
  if (ec == std::errc::result_out_of_range) {
    why = fmt::format("'{}'{}", text::shown(cell), text::out_of_range(cell));
    return false;
  }
  if (ec != std::errc()) {
    why = fmt::format("'{}' is not a number", text::shown(cell));
    return false;
  }
  if (!std::isfinite(out)) {
    why = fmt::format("'{}' is not a finite number", text::shown(cell));
    return false;
  }
  return true;
}

namespace {

// A name or cell as the writer puts it: in double quotes, its quotes doubled, when it holds a comma,
// a quote, a line break or blanks at either end; as it is otherwise.
std::string csv_cell(std::string_view s) {
  const bool plain = s.find_first_of(",\"\r\n") == std::string_view::npos && trim(s).size() == s.size();
  if (plain) return std::string(s);
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + '"';
}

}  // namespace

int CsvTable::column(std::string_view name) const {
  for (std::size_t c = 0; c < header.size(); ++c)
    if (header[c] == name) return int(c);
  return -1;
}

int CsvTable::require_column(std::string_view name) const {
  const int c = column(name);
  if (c < 0) fail(source, header_line, 0, {}, fmt::format("missing column '{}'", text::shown(name)));
  return c;
}

void CsvTable::reject_unknown_columns(const std::vector<std::string>& allowed) const {
  const std::set<std::string> known(allowed.begin(), allowed.end());
  for (std::size_t c = 0; c < header.size(); ++c)
    if (!known.count(header[c])) fail_header(int(c), "unknown column");
}

void CsvTable::keep_as_text(int c) {
  if (text_index_.at(std::size_t(c)) >= 0) return;
  int n = 0;
  for (const int k : text_index_) n += k >= 0;
  text_index_[std::size_t(c)] = n;
}

void CsvTable::fail_header(int column, const std::string& message) const {
  fail(source, header_line, column + 1, header.at(std::size_t(column)), message);
}

void CsvTable::fail_at(std::size_t row, int column, const std::string& message) const {
  fail(source, lines.at(row), column + 1, header.at(std::size_t(column)), message);
}

void CsvTable::refuse_at(std::size_t row, int column, const std::string& message) const {
  throw UsageError(located(source, lines.at(row), column + 1, header.at(std::size_t(column)), message));
}

CsvTable parse_csv(std::string_view text, const std::string& source,
                   const std::function<void(CsvTable&)>& check_header) {
  CsvTable t;
  t.source = source;
  // a UTF-8 byte-order mark (spreadsheets' "CSV UTF-8") is no part of the first name; UTF-16 is refused
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  if (const std::string fault = text::utf16_fault(text); !fault.empty()) fail(source, 1, 0, {}, fault);

  RecordReader records(text, source);
  std::vector<std::string> cells;
  int line = 1;
  // the header: unique, non-empty names
  if (!records.next(cells, line))
    fail(source, 1, 0, {},
         text.empty()
             ? "empty file: expected a header row of column names"
             : "no header row: the file holds nothing but blank lines (expected a header row of column names)");
  std::unordered_map<std::string_view, std::size_t> first_at;  // (a wide header in linear time)
  for (std::size_t c = 0; c < cells.size(); ++c) {
    if (cells[c].empty()) fail(source, line, int(c) + 1, {}, "empty column name in the header");
    if (const auto [at, is_new] = first_at.try_emplace(cells[c], c); !is_new)
      fail(source, line, int(c) + 1, cells[c],
           fmt::format("column name repeated (first at column {})", at->second + 1));
  }
  t.header = std::move(cells);
  t.header_line = line;
  t.text_index_.assign(t.header.size(), -1);
  if (check_header) check_header(t);

  // the rows: as many cells as the header has names, finite numbers but in text columns
  const std::size_t n = t.header.size();
  const auto text_columns =
      std::size_t(std::count_if(t.text_index_.begin(), t.text_index_.end(), [](int k) { return k >= 0; }));
  while (records.next(cells, line)) {
    if (cells.size() < n)
      fail(source, line, int(cells.size()) + 1, t.header[cells.size()],
           fmt::format("missing cell: the row has {} cells, the header {} columns", cells.size(), n));
    if (cells.size() > n)
      fail(source, line, int(n) + 1, {},
           fmt::format("extra cell: the row has {} cells, the header {} columns", cells.size(), n));
    std::vector<double> values(n);
    std::vector<std::string> texts(text_columns);
    std::string why;
    for (std::size_t c = 0; c < n; ++c) {
      if (t.text_index_[c] >= 0)
        texts[std::size_t(t.text_index_[c])] = std::move(cells[c]);
      else if (!parse_number(cells[c], values[c], why))
        fail(source, line, int(c) + 1, t.header[c], why);
    }
    t.rows.push_back(std::move(values));
    t.texts_.push_back(std::move(texts));
    t.lines.push_back(line);
  }
  return t;
}

CsvTable read_csv(const std::string& path, const HeaderCheck& check_header) {
  if (path == "-") {
    const std::string text((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
    return parse_csv(text, "<stdin>", check_header);
  }
  return parse_csv(read_input_file(path), text::shown(path), check_header);
}

std::vector<std::string> joint_columns(const std::vector<std::string>& joint_names, std::string_view prefix) {
  std::vector<std::string> out;
  out.reserve(joint_names.size());
  for (const auto& name : joint_names) out.push_back(std::string(prefix) + name);
  return out;
}

std::vector<int> require_columns(const CsvTable& table, const std::vector<std::string>& names) {
  std::vector<int> out;
  out.reserve(names.size());
  for (const auto& name : names) out.push_back(table.require_column(name));
  return out;
}

std::string format_number(double x) {
  char buf[64];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);  // shortest exact round trip
  return ec == std::errc() ? std::string(buf, end) : std::string("nan");
}

namespace {
// One record of cells, quoted where they need it, ended by a line feed.
std::string csv_record(const std::vector<std::string>& cells) {
  std::string line;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    if (c) line += ',';
    line += csv_cell(cells[c]);
  }
  return line += '\n';
}
}  // namespace

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& header)
    : file_(path), columns_(header.size()) {
  file_.write(csv_record(header));
}

void CsvWriter::row(const std::vector<double>& values, const std::vector<std::string>& text) {
  if (values.size() + text.size() != columns_)
    throw InputError(file_.path() + ": internal error: a row of " + std::to_string(values.size() + text.size()) +
                     " cells for " + std::to_string(columns_) + " columns");
  std::string line;
  for (std::size_t c = 0; c < values.size(); ++c) {
    if (!std::isfinite(values[c]))
      throw InputError(file_.path() + ": row " + std::to_string(rows_written_ + 1) + ", column " +
                       std::to_string(c + 1) + ": the value to write is not finite");
    if (c) line += ',';
    line += format_number(values[c]);
  }
  for (std::size_t c = 0; c < text.size(); ++c) {
    if (c || !values.empty()) line += ',';
    line += csv_cell(text[c]);
  }
  line += '\n';
  file_.write(line);
  ++rows_written_;
}

void CsvWriter::row_cells(const std::vector<std::string>& cells) {
  if (cells.size() != columns_)
    throw InputError(file_.path() + ": internal error: a row of " + std::to_string(cells.size()) + " cells for " +
                     std::to_string(columns_) + " columns");
  file_.write(csv_record(cells));
  ++rows_written_;
}

}  // namespace humandyn::cli
