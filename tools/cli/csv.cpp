#include "cli/csv.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <set>
#include <sstream>

namespace humandyn::cli {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// "<source>: line L, column C 'name': message" (the name when the header gives one)
[[noreturn]] void fail(const std::string& source, int line, int column, std::string_view name,
                       const std::string& message) {
  std::string where = source + ": line " + std::to_string(line);
  if (column > 0) {
    where += ", column " + std::to_string(column);
    if (!name.empty()) where += " '" + std::string(name) + "'";
  }
  throw InputError(where + ": " + message);
}

std::vector<std::string_view> split_cells(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) return cells;
    start = comma + 1;
  }
}

// "'<cell>' <what>", built by appending (GCC 12 warns falsely on "'" + std::string(...)).
std::string quoted(std::string_view cell, std::string_view what) {
  std::string s;
  s.reserve(cell.size() + what.size() + 3);
  s += '\'';
  s += cell;
  s += "' ";
  s += what;
  return s;
}

// A cell as a finite double, or a message saying why it is not one.
bool parse_number(std::string_view cell, double& out, std::string& why) {
  if (cell.empty()) {
    why = "empty cell, expected a number";
    return false;
  }
  // from_chars takes no leading '+'; allow one, but not "+-1"
  std::string_view digits = cell;
  if (digits.front() == '+') {
    digits.remove_prefix(1);
    if (digits.empty() || digits.front() == '-') {
      why = quoted(cell, "is not a number");
      return false;
    }
  }
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), out);
  if (ec == std::errc::result_out_of_range) {
    why = quoted(cell, "is out of the range of a double");
    return false;
  }
  if (ec != std::errc() || end != digits.data() + digits.size()) {
    why = quoted(cell, "is not a number");
    return false;
  }
  if (!std::isfinite(out)) {
    why = quoted(cell, "is not a finite number");
    return false;
  }
  return true;
}

}  // namespace

int CsvTable::column(std::string_view name) const {
  for (std::size_t c = 0; c < header.size(); ++c)
    if (header[c] == name) return int(c);
  return -1;
}

int CsvTable::require_column(std::string_view name) const {
  const int c = column(name);
  if (c < 0) fail(source, 1, 0, {}, "missing column '" + std::string(name) + "'");
  return c;
}

void CsvTable::reject_unknown_columns(const std::vector<std::string>& allowed) const {
  const std::set<std::string> known(allowed.begin(), allowed.end());
  for (std::size_t c = 0; c < header.size(); ++c)
    if (!known.count(header[c])) fail(source, 1, int(c) + 1, header[c], "unknown column");
}

void CsvTable::fail_at(std::size_t row, int column, const std::string& message) const {
  fail(source, lines.at(row), column + 1, header.at(std::size_t(column)), message);
}

CsvTable parse_csv(std::string_view text, const std::string& source, const HeaderCheck& check_header) {
  CsvTable t;
  t.source = source;
  bool have_header = false;
  int line_number = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    // one line, without its \n or \r\n
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (trim(line).empty()) continue;

    const auto cells = split_cells(line);
    if (!have_header) {
      // the header: unique, non-empty names (surrounding double quotes allowed)
      for (std::size_t c = 0; c < cells.size(); ++c) {
        std::string_view name = cells[c];
        if (name.size() >= 2 && name.front() == '"' && name.back() == '"') name = trim(name.substr(1, name.size() - 2));
        if (name.empty()) fail(source, line_number, int(c) + 1, {}, "empty column name in the header");
        for (std::size_t k = 0; k < t.header.size(); ++k)
          if (t.header[k] == name)
            fail(source, line_number, int(c) + 1, name,
                 "column name repeated (first at column " + std::to_string(k + 1) + ")");
        t.header.emplace_back(name);
      }
      have_header = true;
      if (check_header) check_header(t);
      continue;
    }

    // a row: as many finite numbers as the header has names
    const std::size_t n = t.header.size();
    if (cells.size() < n)
      fail(source, line_number, int(cells.size()) + 1, t.header[cells.size()],
           "missing cell: the row has " + std::to_string(cells.size()) + " cells, the header " + std::to_string(n) +
               " columns");
    if (cells.size() > n)
      fail(source, line_number, int(n) + 1, {},
           "extra cell: the row has " + std::to_string(cells.size()) + " cells, the header " + std::to_string(n) +
               " columns");
    std::vector<double> values(n);
    std::string why;
    for (std::size_t c = 0; c < n; ++c)
      if (!parse_number(cells[c], values[c], why)) fail(source, line_number, int(c) + 1, t.header[c], why);
    t.rows.push_back(std::move(values));
    t.lines.push_back(line_number);
  }
  if (!have_header) fail(source, 1, 0, {}, "empty file: expected a header row of column names");
  return t;
}

CsvTable read_csv(const std::string& path, const HeaderCheck& check_header) {
  if (path == "-") {
    const std::string text((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
    return parse_csv(text, "<stdin>", check_header);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path + ": cannot read");
  return parse_csv(text.str(), path, check_header);
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

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& header)
    : file_(path), columns_(header.size()) {
  std::string line;
  for (std::size_t c = 0; c < header.size(); ++c) line += (c ? "," : "") + header[c];
  file_.write(line + '\n');
}

void CsvWriter::row(const std::vector<double>& values) {
  if (values.size() != columns_)
    throw InputError(file_.path() + ": internal error: a row of " + std::to_string(values.size()) + " values for " +
                     std::to_string(columns_) + " columns");
  std::string line;
  for (std::size_t c = 0; c < values.size(); ++c) {
    if (!std::isfinite(values[c]))
      throw InputError(file_.path() + ": row " + std::to_string(rows_written_ + 1) + ", column " +
                       std::to_string(c + 1) + ": the value to write is not finite");
    if (c) line += ',';
    line += format_number(values[c]);
  }
  line += '\n';
  file_.write(line);
  ++rows_written_;
}

}  // namespace humandyn::cli
