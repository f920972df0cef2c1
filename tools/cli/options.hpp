// The command line's options on CLI11: numbers parsed strictly, options that choose one of a few names,
// the layout of `--help`, and CLI11's parse errors as the messages of usage errors.
#pragma once

#include "cli/errors.hpp"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace humandyn::cli {

// A finite number as a CSV cell holds one (decimal, an optional sign and exponent, nothing around it), or none,
// with why in `why` when given (e.g. "'1e-400' is out of the range of a double: too small, it would read as 0").
std::optional<double> read_number(const std::string& text, std::string* why = nullptr);

// `text` with what cannot be seen made visible (text::shown), for the messages of usage errors.
std::string shown(const std::string& text);

// Whether the file name `name` ends in `ending` (".json", ".urdf", ".bvh"), in any case: FILE.JSON as file.json.
bool has_ending(const std::string& name, const std::string& ending);

// `count` finite numbers separated by commas, e.g. "0,0,-9.81", into `out`; false if `text` is not that, with
// why in `why` when given (the first number at fault, or the count).
bool read_numbers(const std::string& text, double* out, std::size_t count, std::string* why = nullptr);

// `--name X`: a finite number into `value` (a double, which keeps its default when the option is absent, or
// a std::optional<double>); UsageError naming the option otherwise.
template <class T>
CLI::Option* add_number(CLI::App& command, const std::string& name, T& value, const std::string& help) {
  return command
      .add_option_function<std::string>(
          name,
          [&value, name](const std::string& text) {
            std::string why;
            const auto x = read_number(text, &why);
            if (!x)
              throw UsageError("option " + name + " needs a finite decimal number (e.g. 0.5, 2, 1e-3), got '" +
                               shown(text) + "': " + why);
            value = *x;
          },
          help)
      ->option_text("X");
}

// `--name K`: a whole number in decimal into `value`.
CLI::Option* add_whole_number(CLI::App& command, const std::string& name, long& value, const std::string& help);

// `--name a|b|c`: one of `choices`' names (the help lists them), its value into `value`; UsageError listing
// the names otherwise.
template <class T>
CLI::Option* add_choice(CLI::App& command, const std::string& name, T& value,
                        std::vector<std::pair<std::string, T>> choices, const std::string& help) {
  std::string listed;
  for (const auto& [text, v] : choices) listed += (listed.empty() ? "" : "|") + text;
  return command
      .add_option_function<std::string>(
          name,
          [&value, name, choices](const std::string& text) {
            std::string names;
            for (std::size_t k = 0; k < choices.size(); ++k) {
              if (choices[k].first == text) {
                value = choices[k].second;
                return;
              }
              names += (k == 0 ? "" : k + 1 == choices.size() ? " or " : ", ") + choices[k].first;
            }
            throw UsageError("unknown " + name + " '" + shown(text) + "' (expected " + names + ")");
          },
          help)
      ->option_text(listed);
}

// The layout of every `--help`: "usage: humandyn <command> [options] <what is required>", the description,
// the options by group; the list of commands shows each one's first line.
class HelpFormatter : public CLI::Formatter {
 public:
  HelpFormatter();
  std::string make_help(const CLI::App* app, std::string name, CLI::AppFormatMode mode) const override;
  std::string make_usage(const CLI::App* app, std::string name) const override;
  std::string make_subcommand(const CLI::App* sub) const override;
  std::string make_option_opts(const CLI::Option* option) const override;
};

// A parse error of `command` (the subcommand parsed, or the whole command line) as one line that names the
// option: an unknown option, an unexpected argument, a missing required option, an option given twice, two
// options that exclude each other, or CLI11's own message.
std::string usage_message(const CLI::ParseError& error, const CLI::App& command);

}  // namespace humandyn::cli
