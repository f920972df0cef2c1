#include "cli/joint_table.hpp"

#include "text/shown.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string_view>

namespace humandyn::cli {

namespace {

// A column name as the eye reads it: without blanks and invisible characters (a tab, a no-break or
// zero-width space, a byte-order mark: text::invisible), in lower case.
std::string loose(const std::string& name) {
  std::string out;
  for (std::size_t i = 0; i < name.size();) {
    const text::CodePoint p = text::decode_utf8(std::string_view(name).substr(i));
    const std::size_t n = p.length == 0 ? 1 : p.length;
    if (p.length == 0 || !(p.c == ' ' || text::invisible(p.c))) out.append(name, i, n);
    i += n;
  }
  for (char& ch : out) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  return out;
}

}  // namespace

JointTable::JointTable(const std::string& path, const std::vector<ColumnGroup>& groups,
                       const std::vector<std::string>& reserved, const std::vector<std::string>& read_as_text,
                       StateForm form, const std::vector<std::string>& written)
    : columns_(groups.size()) {
  std::vector<std::string> text = read_as_text;
  if (form != StateForm::Any) text.push_back("form");
  const auto known = [&](const std::string& name) {
    if (name == "t" || std::find(text.begin(), text.end(), name) != text.end()) return true;
    for (const auto& g : groups)
      if (std::find(g.columns.begin(), g.columns.end(), name) != g.columns.end()) return true;
    return false;
  };
  // the header is checked before any row is read, so a missing or misspelt column is reported first
  csv_ = read_csv(path, [&](CsvTable& table) {
    for (std::size_t c = 0; c < table.header.size(); ++c) {
      const std::string& name = table.header[c];
      if (std::find(written.begin(), written.end(), name) != written.end())
        table.fail_header(int(c),
                          "a column this command writes (its result), not one it reads: remove it, or "
                          "rename it to carry it through");
      if (known(name)) continue;
      // a column the command reads, written in other case or with blanks or invisible characters, would
      // pass through unread
      const std::string seen = loose(name);
      for (const auto& prefix : reserved)
        if (seen.starts_with(prefix))
          table.fail_header(int(c), "unknown column: " + prefix +
                                        " starts the command's own columns, and this is none it reads here (a "
                                        "misspelling, or a column to rename to carry it through)");
      for (const auto& t : text)
        if (seen == t) table.fail_header(int(c), "unknown column: the command reads '" + t + "'");
      if (seen == "t") table.fail_header(int(c), "unknown column: the command reads 't'");
      passed_.push_back(int(c));
    }
    for (std::size_t g = 0; g < groups.size(); ++g) {
      const auto& columns = groups[g].columns;
      if (groups[g].use == ColumnGroup::Ignored) continue;
      if (groups[g].use == ColumnGroup::Optional &&
          std::none_of(columns.begin(), columns.end(), [&](const std::string& n) { return table.column(n) >= 0; }))
        continue;
      columns_[g] = require_columns(table, columns);
    }
    for (const int c : passed_) table.keep_as_text(c);
    for (const auto& name : text)
      if (const int c = table.column(name); c >= 0) table.keep_as_text(c);
  });
  t_col_ = csv_.column("t");
  if (form == StateForm::Any || csv_.column("form") < 0) return;
  for (std::size_t r = 0; r < rows(); ++r) {
    const std::string& cell = *this->text(r, "form");
    if (cell != "floating")
      fail_at(r, "form",
              "'" + text::shown(cell) + "' is no form of the body (the column says 'floating' on every row)");
    if (form == StateForm::StanceRooted)
      refuse_at(r, "form",
                "a state of the floating form (its base_ columns are the pelvis's, its re-hung leg's angles its "
                "own), where the stance-rooted form's is read (id and fd read it with --floating)");
  }
}

std::string JointTable::where(std::size_t row) const {
  return csv_.source + ": line " + std::to_string(csv_.lines[row]) + ": ";
}

void JointTable::read(std::size_t row, std::size_t group, Eigen::Ref<Eigen::VectorXd> v) const {
  const auto& cols = columns_[group];
  if (cols.empty()) {
    v.setZero();
    return;
  }
  const auto& cells = csv_.rows[row];
  for (std::size_t i = 0; i < cols.size(); ++i) v[Eigen::Index(i)] = cells[std::size_t(cols[i])];
}

void JointTable::read(std::size_t row, std::size_t group, const std::vector<std::size_t>& joints,
                      Eigen::Ref<Eigen::VectorXd> v) const {
  const auto& cols = columns_[group];
  const auto& cells = csv_.rows[row];
  for (std::size_t k = 0; k < joints.size(); ++k)
    v[Eigen::Index(joints[k])] = cols.empty() ? 0.0 : cells[std::size_t(cols[k])];
}

const std::string* JointTable::text(std::size_t row, const std::string& name) const {
  const int c = csv_.column(name);
  return c < 0 ? nullptr : &csv_.text(row, c);
}

void JointTable::fail_at(std::size_t row, const std::string& name, const std::string& message) const {
  csv_.fail_at(row, csv_.column(name), message);
}

void JointTable::refuse_at(std::size_t row, const std::string& name, const std::string& message) const {
  csv_.refuse_at(row, csv_.column(name), message);
}

std::vector<std::string> JointTable::header(const std::vector<std::string>& results) const {
  std::vector<std::string> h;
  if (has_time()) h.push_back("t");
  for (const int c : passed_) {
    const std::string& name = csv_.header[std::size_t(c)];
    if (std::find(results.begin(), results.end(), name) != results.end())
      csv_.fail_header(c, "this column is passed through to the output, which writes its own column of that name");
    h.push_back(name);
  }
  h.insert(h.end(), results.begin(), results.end());
  return h;
}

void JointTable::write(CsvWriter& out, std::size_t row, const std::vector<std::optional<double>>& values,
                       const std::vector<std::string>& what) const {
  std::vector<std::string> cells;
  cells.reserve(values.size() + passed_.size() + 1);
  if (has_time()) cells.push_back(format_number(time(row)));
  for (const int c : passed_) cells.push_back(csv_.text(row, c));
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (!values[k]) {
      cells.emplace_back();
      continue;
    }
    // finite inputs give finite results unless a number overflowed (e.g. qd = 1e200)
    if (!std::isfinite(*values[k]))
      throw InputError(where(row) + "the " + what[k] + " overflows at this state (its numbers are too large)");
    cells.push_back(format_number(*values[k]));
  }
  out.row_cells(cells);
}

}  // namespace humandyn::cli
