// libFuzzer target: the CSV state reader fed arbitrary bytes. Every input must give a table or a
// humandyn::cli::InputError; a crash, a hang, a sanitizer report, any other exception or a table that
// breaks the reader's promises (below) is a bug. Links humandyn_cli_support (the reader, with fmt);
// seeds in tests/data/fuzz/csv.
#include "cli/csv.hpp"
#include "text/shown.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <set>
#include <string>
#include <string_view>

namespace {

// No control byte reaches the terminal: messages show every name and cell through shown().
void check_printable(std::string_view text) {
  for (const char c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  using humandyn::cli::CsvTable;
  // half the inputs go through a header check as the subcommands' (unknown and missing columns)
  const bool checked = size > 0 && (data[size - 1] & 1) != 0;
  const humandyn::cli::HeaderCheck check = [](const CsvTable& t) {
    t.reject_unknown_columns({"t", "q_a", "qd_a", "q,b", " q_c"});
    t.require_column("t");
  };
  try {
    const CsvTable t = humandyn::cli::parse_csv(text, "fuzz.csv", checked ? check : humandyn::cli::HeaderCheck{});
    // the promises: unique non-empty names, every row as wide as the header and finite, rows in file order
    std::set<std::string> names;
    for (const auto& name : t.header) {
      if (name.empty() || !names.insert(name).second) std::abort();
      check_printable(humandyn::text::shown(name));
    }
    if (t.rows.size() != t.lines.size()) std::abort();
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
      if (t.rows[r].size() != t.header.size()) std::abort();
      for (const double x : t.rows[r])
        if (!std::isfinite(x)) std::abort();
      if (t.lines[r] <= t.header_line || (r > 0 && t.lines[r] <= t.lines[r - 1])) std::abort();
    }
  } catch (const humandyn::cli::InputError& e) {
    check_printable(e.what());
  }
  return 0;
}
