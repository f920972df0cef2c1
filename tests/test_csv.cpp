// The CSV reader's strictness: a UTF-8 byte-order mark is dropped, quoted cells follow RFC 4180
// (commas, line breaks and doubled quotes inside quotes, CRLF line ends), a misplaced quote is an error
// naming file, line and column, and messages show what cannot be seen (a BOM, a tab, a trailing blank).
// Then `humandyn id` on a spreadsheet's "CSV UTF-8" file gives the torques of the same file unmarked.
#include "cli/csv.hpp"
#include "humandyn/humandyn.hpp"
#include "support/cli_run.hpp"
#include "support/random_state.hpp"
#include "text/shown.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace test_csv {

namespace {

using namespace humandyn::cli;
namespace fs = std::filesystem;
using humandyn::testing::CliRun;
using humandyn::testing::humandyn_cli;
using humandyn::testing::input_error;
using humandyn::testing::read_text;
using humandyn::testing::Scratch;
using humandyn::testing::write_text;
using Names = std::vector<std::string>;

const std::string bom = "\xEF\xBB\xBF";

// ---- the byte-order mark ---------------------------------------------------------------------------

TEST(CsvBom, AUtf8MarkAtTheStartIsDroppedAndTheFileReadsAsWithoutIt) {
  const std::string text = "t,q_a\n0,1.5\n";
  const CsvTable plain = parse_csv(text, "s.csv");
  const CsvTable marked = parse_csv(bom + text, "s.csv");
  EXPECT_EQ(marked.header, (Names{"t", "q_a"}));
  EXPECT_EQ(marked.header, plain.header);
  EXPECT_EQ(marked.rows, plain.rows);
  EXPECT_EQ(marked.lines, plain.lines);
  // with nothing after it, it is an empty file like any other
  EXPECT_EQ(input_error([&] { parse_csv(bom, "s.csv"); }),
            "s.csv: line 1: empty file: expected a header row of column names");
}

TEST(CsvBom, AMarkAnywhereElseIsPartOfTheTextAndShowsInMessages) {
  const auto check = [](const CsvTable& t) { t.reject_unknown_columns({"t", "q_a"}); };
  // two marks: the second is no mark but a character glued to the name
  EXPECT_EQ(input_error([&] { parse_csv(bom + bom + "t,q_a\n", "s.csv", check); }),
            "s.csv: line 1, column 1 '<U+FEFF>t': unknown column");
  EXPECT_EQ(input_error([&] { parse_csv("t,\xEF\xBB\xBFq_a\n", "s.csv", check); }),
            "s.csv: line 1, column 2 '<U+FEFF>q_a': unknown column");
}

TEST(CsvBom, Utf16IsRefusedWithAReason) {
  for (const std::string mark : {"\xFF\xFE", "\xFE\xFF"})
    EXPECT_EQ(input_error([&] { parse_csv(mark + "t\n", "s.csv"); }),
              "s.csv: line 1: the file is UTF-16 (it starts with a UTF-16 byte-order mark): save it as UTF-8");
}

// ---- RFC 4180 quoting ------------------------------------------------------------------------------

TEST(CsvQuotes, QuotedCellsHoldCommasQuotesBlanksAndLineBreaks) {
  const CsvTable t = parse_csv(
      "\"t\",\"q,a\",\"q\"\"b\",\" q_c \", \"q_d\" ,\"q\ne\"\r\n"
      "\"1\",2,\"-3.5\",  \"4\"  ,5,6\r\n"
      "\r\n"
      "0,0,0,0,\"1e-3\",\"+7\"\r\n",
      "s.csv");
  EXPECT_EQ(t.header, (Names{"t", "q,a", "q\"b", " q_c ", "q_d", "q\ne"}));
  EXPECT_EQ(t.header_line, 1);
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0], (std::vector<double>{1, 2, -3.5, 4, 5, 6}));
  EXPECT_EQ(t.rows[1], (std::vector<double>{0, 0, 0, 0, 0.001, 7}));
  EXPECT_EQ(t.lines, (std::vector<int>{3, 5}));  // the header spans lines 1 and 2; line 4 is blank
  EXPECT_EQ(t.column("q,a"), 1);
  EXPECT_EQ(t.column("q\"b"), 2);
}

TEST(CsvQuotes, EmptyQuotedCellsAreCellsNotBlankLines) {
  // "" on a line of its own is a row with one empty cell, not a blank line to skip
  EXPECT_EQ(input_error([] { parse_csv("a\n\"\"\n", "s.csv"); }),
            "s.csv: line 2, column 1 'a': empty cell, expected a number");
  EXPECT_EQ(input_error([] { parse_csv("\"\",b\n", "s.csv"); }),
            "s.csv: line 1, column 1: empty column name in the header");
  // and quoting does not make two names different
  EXPECT_EQ(input_error([] { parse_csv("a,\"a\"\n", "s.csv"); }),
            "s.csv: line 1, column 2 'a': column name repeated (first at column 1)");
}

TEST(CsvQuotes, AMalformedQuoteIsAnErrorWithLineAndColumn) {
  struct Case {
    const char* text;
    const char* message;
  };
  const Case cases[] = {
      {"a\"b,c\n",
       "s.csv: line 1, column 1: a quote inside an unquoted cell (quote the whole cell and write a quote in it twice: "
       "\"a\"\"b\")"},
      {"a,b\n1,2\"\n",
       "s.csv: line 2, column 2: a quote inside an unquoted cell (quote the whole cell and write a quote in it twice: "
       "\"a\"\"b\")"},
      {"\"a\"b,c\n",
       "s.csv: line 1, column 1: 'b' after the closing quote (a quote inside a quoted cell is written twice: \"\")"},
      {"a,b\n1,\"2\" 3\t\n",
       "s.csv: line 2, column 2: '3\\t' after the closing quote (a quote inside a quoted cell is written twice: \"\")"},
      // a lone \r after the closing quote ends the line (CsvLineEnds): the next one is short of a cell
      {"a,b\n1,\"2\"\r3\n", "s.csv: line 3, column 2 'b': missing cell: the row has 1 cells, the header 2 columns"},
      {"a,\"b\n1,2\n", "s.csv: line 1, column 2: the quote that opens this cell is never closed"},
      {"a\n\n\"1\n", "s.csv: line 3, column 1: the quote that opens this cell is never closed"},
      // a line break inside quotes moves the lines on: the error is on the line where it is found
      {"\"a\nb\",c\n1,x\n", "s.csv: line 3, column 2 'c': 'x' is not a number"},
  };
  for (const auto& c : cases) EXPECT_EQ(input_error([&] { parse_csv(c.text, "s.csv"); }), c.message) << c.text;
}

// ---- line ends ---------------------------------------------------------------------------------------

TEST(CsvLineEnds, LoneCarriageReturnsEndLinesAsLineFeedsDo) {
  // old Mac OS line ends (a spreadsheet's "CSV (Macintosh)"): every row read, on the lines counted so
  const std::string lf = "t,q_a,note\n0,0.5,\"x\ny\"\n\n0.01,-1,z\n";
  for (const std::string& text : {lf, std::string("t,q_a,note\r0,0.5,\"x\ry\"\r\r0.01,-1,z\r"),
                                  std::string("t,q_a,note\r\n0,0.5,\"x\r\ny\"\r\n\r\n0.01,-1,z")}) {
    const CsvTable t = parse_csv(text, "s.csv", [](CsvTable& table) { table.keep_as_text(2); });
    EXPECT_EQ(t.header, (Names{"t", "q_a", "note"})) << text;
    ASSERT_EQ(t.rows.size(), 2u) << text;
    EXPECT_EQ(t.rows[0][1], 0.5);
    EXPECT_EQ(t.rows[1][1], -1);
    EXPECT_EQ(t.lines, (std::vector<int>{2, 5})) << text;  // the quoted cell spans lines 2 and 3; 4 is blank
  }
  // and errors name the line a lone \r ends
  EXPECT_EQ(input_error([] { parse_csv("a,b\r1,2\r3,x\r", "s.csv"); }),
            "s.csv: line 3, column 2 'b': 'x' is not a number");
}

TEST(CsvQuotes, TheWriterQuotesNamesThatNeedItAndTheyReadBack) {
  Scratch dir;
  const Names names{"t", "tau_a,b", "tau_\"c\"", " tau_d", "tau_e\t", "tau_plain"};
  const fs::path path = dir / "out.csv";
  {
    CsvWriter w(path.string(), names);
    w.row({0, 1, 2, 3, 4, 5});
    w.commit();
  }
  EXPECT_EQ(read_text(path), "t,\"tau_a,b\",\"tau_\"\"c\"\"\",\" tau_d\",\"tau_e\t\",tau_plain\n0,1,2,3,4,5\n");
  const CsvTable t = read_csv(path.string());
  EXPECT_EQ(t.header, names);
  EXPECT_EQ(t.rows, (std::vector<std::vector<double>>{{0, 1, 2, 3, 4, 5}}));
}

// ---- invisible characters in messages --------------------------------------------------------------

// The one rule of the command line's and the URDF importer's messages (text/shown.hpp).
TEST(CsvShown, WhatCannotBeSeenIsShown) {
  struct Case {
    std::string text, shown;
  };
  const Case cases[] = {
      {"q_a", "q_a"},
      {"q_a ", "q_a\u2420"},                      // a trailing blank
      {" q_a", "\u2420q_a"},                      // a leading one
      {"  hip  x ", "\u2420\u2420hip  x\u2420"},  // the blanks of a run at either end, not those inside
      {"q\ta", "q\\ta"},                          // tab, line feed, carriage return as C escapes
      {"q\r\n", "q\\r\\n"},
      {"a\tb\n", "a\\tb\\n"},
      {"a\\b", "a\\\\b"},  // so a backslash is doubled
      {bom + "t", "<U+FEFF>t"},
      {"\x01\x1F\x7F", "<U+0001><U+001F><U+007F>"},
      {"a\xC2\xA0"
       "b",
       "a<U+00A0>b"},  // no-break space
      {"a\xE2\x80\x8B"
       "b",
       "a<U+200B>b"},                  // zero-width space
      {"a\xE2\x80\x8F", "a<U+200F>"},  // right-to-left mark
      {"h\xC3\xBC"
       "ft_\xE5\xB7\xA6",
       "h\xC3\xBC"
       "ft_\xE5\xB7\xA6"},  // visible non-ASCII is kept as it is
      {"\xFF"
       "a\xC3",
       "<0xFF>a<0xC3>"},  // bytes that are not UTF-8
      {"\xEF\xBB\xBFhip\xFF", "<U+FEFF>hip<0xFF>"},
      {"\xC0\xAF", "<0xC0><0xAF>"},            // an overlong form
      {"\xED\xA0\x80", "<0xED><0xA0><0x80>"},  // a surrogate
      {"\xF8\x80\x80", "<0xF8><0x80><0x80>"},  // no UTF-8 sequence starts with 0xF8
      {"", ""},
  };
  for (const auto& c : cases) EXPECT_EQ(humandyn::text::shown(c.text), c.shown) << c.shown;
}

TEST(CsvShown, MessagesShowInvisibleCharactersInNamesAndCells) {
  const auto check = [](const CsvTable& t) {
    t.reject_unknown_columns({"t", "q_a"});
    t.require_column("q_a");
  };
  EXPECT_EQ(input_error([&] { parse_csv("t,\"q_a \"\n", "s.csv", check); }),
            "s.csv: line 1, column 2 'q_a\u2420': unknown column");
  EXPECT_EQ(input_error([&] { parse_csv("t,\"q_a\t\"\n", "s.csv", check); }),
            "s.csv: line 1, column 2 'q_a\\t': unknown column");
  EXPECT_EQ(input_error([&] { parse_csv("\n\nt\n", "s.csv", check); }), "s.csv: line 3: missing column 'q_a'");
  EXPECT_EQ(input_error([] { CsvTable().require_column("q_a\xC2\xA0"); }), ": line 1: missing column 'q_a<U+00A0>'");
  EXPECT_EQ(input_error([] { parse_csv("a\n\"1 \"\n", "s.csv"); }),
            "s.csv: line 2, column 1 'a': '1\u2420' is not a number");
  EXPECT_EQ(input_error([] { parse_csv("a\n1\xE2\x80\x8B\n", "s.csv"); }),
            "s.csv: line 2, column 1 'a': '1<U+200B>' is not a number");
  EXPECT_EQ(input_error([] { parse_csv("a\n1\x01\n", "s.csv"); }),
            "s.csv: line 2, column 1 'a': '1<U+0001>' is not a number");
}

// ---- the command line ------------------------------------------------------------------------------

// `humandyn id <arguments> --in <file>` on `text` with and without a byte-order mark: the same output.
void expect_bom_ignored(const Scratch& dir, const std::string& arguments, const std::string& text) {
  write_text(dir / "plain.csv", text);
  write_text(dir / "marked.csv", bom + text);
  const CliRun plain = humandyn_cli(dir, "id " + arguments + " --in plain.csv");
  const CliRun marked = humandyn_cli(dir, "id " + arguments + " --in marked.csv");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(marked.exit_code, 0) << marked.err;
  EXPECT_EQ(marked.err, "");
  const CsvTable out = parse_csv(marked.out, "stdout");
  EXPECT_EQ(out.rows.size(), parse_csv(text, "in").rows.size());
  EXPECT_EQ(marked.out, plain.out);
}

// A state file of `rows` random states of the default body: t, q_, qd_, qdd_ of every joint, the header's
// names in `quote`s, each line ended by `line_end`.
std::string state_file(int rows, unsigned seed, const std::string& quote, const std::string& line_end) {
  const auto d = humandyn::human_description(humandyn::default_parameters());
  const auto states = humandyn::testing::random_states(16, rows, seed);
  std::string text = quote + "t" + quote;
  for (const char* prefix : {"q_", "qd_", "qdd_"})
    for (const auto& j : d.joints) text.append(",").append(quote).append(prefix).append(j.name).append(quote);
  text += line_end;
  for (std::size_t r = 0; r < states.size(); ++r) {
    text += format_number(0.01 * double(r));
    for (const auto* v : {&states[r].q, &states[r].qd, &states[r].qdd})
      for (int i = 0; i < v->size(); ++i) text.append(",").append(format_number((*v)[i]));
    text += line_end;
  }
  return text;
}

TEST(CliCsv, AStateFileWithAByteOrderMarkGivesTheTorquesOfTheFileWithout) {
  Scratch dir;
  expect_bom_ignored(dir, "", state_file(4, 7, "\"", "\r\n"));  // a spreadsheet's way: quoted names, CRLF
}

TEST(CliCsv, AStateFileWithOldMacLineEndsGivesEveryRowsTorques) {
  Scratch dir;
  const std::string text = state_file(3, 11, "", "\n");
  std::string mac = text;
  std::replace(mac.begin(), mac.end(), '\n', '\r');
  write_text(dir / "plain.csv", text);
  write_text(dir / "mac.csv", mac);
  const CliRun plain = humandyn_cli(dir, "id --in plain.csv");
  const CliRun read = humandyn_cli(dir, "id --in mac.csv");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(read.exit_code, 0) << read.err;
  EXPECT_EQ(parse_csv(read.out, "stdout").rows.size(), 3u);
  EXPECT_EQ(read.out, plain.out);
}

TEST(CliCsv, TheSpreadsheetCaseReadsAsWithoutTheMark) {
#ifndef HUMANDYN_CLI_READS_URDF
  GTEST_SKIP() << "the command line is built without the URDF importer: the case's model is a URDF file";
#endif
  const fs::path cases = fs::path(HUMANDYN_SHARED_DATA) / ".." / "cases" / "csv-bom";
  if (!fs::exists(cases / "excel_utf8_sig.csv"))
    GTEST_SKIP() << "the shared data folder is absent (" << cases << "): the spreadsheet's file is not here";
  Scratch dir;
  const std::string marked = read_text(cases / "excel_utf8_sig.csv");
  ASSERT_EQ(marked.substr(0, 3), bom) << "the case file should start with a byte-order mark";
  fs::copy_file(cases / "arm2.urdf", dir / "arm2.urdf");
  expect_bom_ignored(dir, "--model arm2.urdf", marked.substr(3));
  // and the case's own file, as it is
  fs::copy_file(cases / "excel_utf8_sig.csv", dir / "excel_utf8_sig.csv");
  const CliRun run = humandyn_cli(dir, "id --model arm2.urdf --in excel_utf8_sig.csv");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out, humandyn_cli(dir, "id --model arm2.urdf --in plain.csv").out);
}

}  // namespace

}  // namespace test_csv
