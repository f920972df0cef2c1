#include "cli/options.hpp"

#include "cli/csv.hpp"
#include "text/shown.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <utility>

namespace humandyn::cli {

std::optional<double> read_number(const std::string& text, std::string* why) {
  double x = 0;
  std::string fault;
  if (!parse_number(text, x, fault)) {  // (the CSV cells' rule: decimal, finite)
    if (why) *why = text.empty() ? "an empty value, expected a number" : std::move(fault);
    return std::nullopt;
  }
  return x;
}

std::string shown(const std::string& text) { return text::shown(text); }

bool has_ending(const std::string& name, const std::string& ending) {
  if (name.size() <= ending.size()) return false;  // the ending alone names no file
  const auto lower = [](char ch) { return char(std::tolower(static_cast<unsigned char>(ch))); };
  return std::equal(ending.begin(), ending.end(), name.end() - std::ptrdiff_t(ending.size()),
                    [&](char a, char b) { return lower(a) == lower(b); });
}

bool read_numbers(const std::string& text, double* out, std::size_t count, std::string* why) {
  std::size_t from = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t comma = k + 1 < count ? text.find(',', from) : text.size();
    if (comma == std::string::npos) {
      if (why) *why = fmt::format("{} of the {} numbers it needs", k + 1, count);
      return false;
    }
    if (k + 1 == count && text.find(',', from) != std::string::npos) {
      if (why) *why = fmt::format("more than the {} numbers it needs", count);
      return false;
    }
    const auto x = read_number(text.substr(from, comma - from), why);
    if (!x) return false;
    out[k] = *x;
    from = comma + 1;
  }
  return true;
}

CLI::Option* add_whole_number(CLI::App& command, const std::string& name, long& value, const std::string& help) {
  return command
      .add_option_function<std::string>(
          name,
          [&value, name](const std::string& text) {
            char* end = nullptr;
            errno = 0;
            const long k = std::strtol(text.c_str(), &end, 10);
            // (strtol skips leading blanks, which a decimal number may not have either)
            if (text.empty() || std::isspace(static_cast<unsigned char>(text[0])) || *end != '\0' || errno == ERANGE)
              throw UsageError(fmt::format("option {} needs a whole number, got '{}'", name, text::shown(text)));
            value = k;
          },
          help)
      ->option_text("K");
}

HelpFormatter::HelpFormatter() { column_width(21); }

std::string HelpFormatter::make_help(const CLI::App* app, std::string name, CLI::AppFormatMode) const {
  std::string text = make_usage(app, name) + "\n";
  if (app->get_parent() == nullptr) {  // the list of commands
    text += "commands:\n";
    for (const CLI::App* sub : app->get_subcommands({})) text += make_subcommand(sub);
    return text + "\n`" + name + " <command> --help` describes a command's options.\n";
  }
  text += app->get_description() + "\n";
  for (const std::string& group : app->get_groups()) {
    text += "\n" + group + ":\n";
    for (const CLI::Option* o : app->get_options([&](const CLI::Option* o) { return o->get_group() == group; }))
      text += make_option(o, o->get_positional());
  }
  if (const auto subs = app->get_subcommands({}); !subs.empty()) {  // motion: import, export
    text += "\ncommands:\n";
    for (const CLI::App* sub : subs) text += make_subcommand(sub);
    text += "\n`" + name + " <command> --help` describes a command's options.\n";
  }
  if (!app->get_footer().empty()) text += "\n" + app->get_footer() + "\n";
  return text;
}

std::string HelpFormatter::make_usage(const CLI::App* app, std::string name) const {
  if (app->get_parent() == nullptr) return "usage: " + name + " <command> [options]\n";
  std::string line = "usage: " + name + (app->get_subcommands({}).empty() ? " [options]" : " <command> [options]");
  for (const CLI::Option* o : app->get_options())
    if (o->get_required())
      line += " " + (o->get_positional() ? o->get_name(true, false) : o->get_name() + " " + o->get_option_text());
  return line + "\n";
}

std::string HelpFormatter::make_option_opts(const CLI::Option* option) const {
  return option->get_option_text().empty() ? "" : " " + option->get_option_text();
}

std::string HelpFormatter::make_subcommand(const CLI::App* sub) const {
  const std::string& d = sub->get_description();
  return fmt::format("  {:<10} {}\n", sub->get_name(), d.substr(0, d.find('\n')));
}

std::string usage_message(const CLI::ParseError& error, const CLI::App& command) {
  const std::vector<const CLI::Option*> options = command.get_options();
  // an argument not understood comes first: it may be the misspelt required option
  const bool extras_or_required =
      dynamic_cast<const CLI::ExtrasError*>(&error) || dynamic_cast<const CLI::RequiredError*>(&error);
  if (const auto extra = command.remaining(); extras_or_required && !extra.empty()) {
    const std::string& arg = extra.front();
    if (arg.size() > 1 && arg[0] == '-') return "unknown option " + shown(arg.substr(0, arg.find('=')));
    if (const auto subs = command.get_subcommands({}); !subs.empty() && command.get_subcommands().empty()) {
      std::vector<std::string> names;  // motion imprt
      for (const CLI::App* sub : subs) names.push_back(sub->get_name());
      return fmt::format("unknown command '{}' (expected {})", shown(arg), fmt::join(names, " or "));
    }
    return "unexpected argument '" + shown(arg) + "'";
  }
  if (const auto subs = command.get_subcommands({});
      dynamic_cast<const CLI::RequiredError*>(&error) && !subs.empty() && command.get_subcommands().empty()) {
    std::vector<std::string> names;
    for (const CLI::App* sub : subs) names.push_back(sub->get_name());
    return fmt::format("a command is needed: {}", fmt::join(names, " or "));
  }
  if (dynamic_cast<const CLI::RequiredError*>(&error))
    for (const CLI::Option* o : options)
      if (o->get_required() && o->count() == 0 && !o->get_positional())
        return "option " + o->get_name() + " is required";
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&error))
    for (const CLI::Option* o : options)
      if (o->get_expected_max() == 1 && o->get_type_size() > 0 && o->count() > 1)
        return "option " + o->get_name() + " given more than once";
  if (dynamic_cast<const CLI::ExcludesError*>(&error))  // named as defined: the later does not go with the earlier
    for (std::size_t i = 0; i < options.size(); ++i)
      for (std::size_t j = i + 1; j < options.size(); ++j)
        if (options[i]->count() > 0 && options[j]->count() > 0 &&
            options[i]->get_excludes().count(const_cast<CLI::Option*>(options[j])) > 0)
          return options[j]->get_name() + " does not go with " + options[i]->get_name();
  return error.what();
}

}  // namespace humandyn::cli
