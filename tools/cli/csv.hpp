// CSV files of numbers with a header row of column names, as the subcommands read and write them
// (joint states in, torques out). Reading is strict: every error names the file, the line and the
// column, so that a bad cell is found at once and never becomes a silent NaN.
//
//   t,q_r_ankle_pitch,qd_r_ankle_pitch,...      header: unique, non-empty names
//   0,0.1,0,...                                 one row per state: finite numbers, as many as names
//
// The syntax is RFC 4180's: a cell in double quotes may hold commas, line breaks and quotes (written
// twice, ""), so that any name can be a column; a quote anywhere else is an error. Blank lines are
// skipped, blanks around a cell are padding (inside quotes they are kept), line ends may be \n,
// \r\n or a lone \r, and a UTF-8 byte-order mark at the start is dropped. The path "-" reads standard input and
// writes standard output. Columns a reader marks as text (keep_as_text, from its header check) keep
// their cells as written (e.g. a stance foot "right", a phase "flight"); every other cell is a number.
#pragma once

#include "cli/atomic_file.hpp"
#include "cli/errors.hpp"

#include <cstdio>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace humandyn::cli {

class CsvTable {
 public:
  std::string source;                     // the file name, as messages quote it
  std::vector<std::string> header;        // column names
  std::vector<std::vector<double>> rows;  // a text column's cells are 0 here: see text()
  std::vector<int> lines;                 // the 1-based line of each row in the file (where the row starts)
  int header_line = 1;

  // Marks column `c` as text, from a header check: its cells are kept as written (without padding).
  void keep_as_text(int c);
  bool is_text(int c) const { return text_index_.at(std::size_t(c)) >= 0; }
  // The cell of text column `c` in row `r`.
  const std::string& text(std::size_t r, int c) const { return texts_[r][std::size_t(text_index_[std::size_t(c)])]; }

  // Index of the column called `name`, -1 if there is none.
  int column(std::string_view name) const;

  // Index of the column called `name`; InputError naming the file and the header line if absent.
  int require_column(std::string_view name) const;

  // InputError unless every column is one of `allowed`; the message names the first stranger and
  // its position in the header.
  void reject_unknown_columns(const std::vector<std::string>& allowed) const;

  // "<source>: line <line of row r>, column <c+1> '<name>': <message>", for errors a caller finds in a
  // cell after reading (e.g. an angle out of range).
  [[noreturn]] void fail_at(std::size_t row, int column, const std::string& message) const;
  // As fail_at, a UsageError (exit code 2): a well-formed cell that does not go with the options given.
  [[noreturn]] void refuse_at(std::size_t row, int column, const std::string& message) const;
  // "<source>: line <header line>, column <c+1> '<name>': <message>", about a column of the header.
  [[noreturn]] void fail_header(int column, const std::string& message) const;

 private:
  friend CsvTable parse_csv(std::string_view, const std::string&, const std::function<void(CsvTable&)>&);
  std::vector<int> text_index_;                  // per column: its place among the text columns, -1 for numbers
  std::vector<std::vector<std::string>> texts_;  // per row: the text columns' cells
};

// Called with the table once its header is read, before any row: lets a caller report a missing or
// unknown column before the cells below it, and mark the columns it reads as text.
using HeaderCheck = std::function<void(CsvTable&)>;

// Parses CSV text; `source` names it in error messages. Throws InputError.
CsvTable parse_csv(std::string_view text, const std::string& source, const HeaderCheck& check_header = {});

// Reads and parses a file ("-": standard input). Throws InputError.
CsvTable read_csv(const std::string& path, const HeaderCheck& check_header = {});

// A cell as a finite double (blanks already trimmed), or false with `why` saying why it is not one
// ("empty cell, expected a number", "'x' is not a number", ...): for text columns read as numbers.
bool parse_number(std::string_view cell, double& out, std::string& why);

// The column names `<prefix><joint>` for every joint, e.g. joint_columns(names, "q_").
std::vector<std::string> joint_columns(const std::vector<std::string>& joint_names, std::string_view prefix);

// For each name in `names`, its column in `table`; InputError for the first one missing.
std::vector<int> require_columns(const CsvTable& table, const std::vector<std::string>& names);

// A number as CSV writes it: the shortest form that reads back to the same double ("%.17g" precision).
std::string format_number(double x);

// Writes a CSV file all or nothing (cli/atomic_file.hpp), header names quoted where RFC 4180 needs it:
// `path` is replaced only on commit(); destroyed without commit() (an error half-way), it leaves `path`
// as it was. "-": standard output.
class CsvWriter {
 public:
  CsvWriter(const std::string& path, const std::vector<std::string>& header);

  // One row: the numbers, then the text cells (quoted here where needed); InputError if its size differs
  // from the header's or a number is not finite.
  void row(const std::vector<double>& values, const std::vector<std::string>& text = {});
  // One row of cells already written as text (format_number for numbers; quoted here where needed);
  // InputError if its size differs from the header's.
  void row_cells(const std::vector<std::string>& cells);
  void commit() { file_.commit(); }
  AtomicFile& file() { return file_; }  // (for commit_together)

 private:
  AtomicFile file_;
  std::size_t columns_ = 0;
  std::size_t rows_written_ = 0;
};

}  // namespace humandyn::cli
