// humandyn: the command line. `humandyn <command> [options]`; `humandyn help` lists the commands.
#include "cli/atomic_file.hpp"
#include "cli/commands.hpp"
#include "cli/errors.hpp"
#include "cli/model_source.hpp"
#include "cli/options.hpp"
#include "cli/print.hpp"
#include "humandyn/model.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace {

// What every command's arguments obey, once parsed: no empty value (a file name, a number or a title is
// expected), no flag given twice (as no option taking a value may be), standard input ("-") read by one
// option only; and each output file named by one file argument only (the options and positionals below:
// the values of others are no files).
void check_arguments(const CLI::App& command) {
  namespace cli = humandyn::cli;
  std::vector<std::pair<std::string, std::string>> arguments;
  std::vector<std::string> from_stdin;
  const std::vector<std::string> outputs = {"--out", "--model-out", "--urdf", "--json", "--csv"};
  const std::vector<std::string> inputs = {"--in",     "--model", "--track", "--start",   "--torques", "--map",
                                           "--joints", "states",  "STATES",  "FILE.urdf", "CLIP"};
  const auto among = [](const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  std::vector<const CLI::App*> apps = {&command};
  for (std::size_t k = 0; k < apps.size(); ++k) {
    for (const CLI::App* sub : apps[k]->get_subcommands()) apps.push_back(sub);
    for (const CLI::Option* option : apps[k]->get_options()) {
      const std::string name = option->get_name();
      if (option->get_expected_max() == 0) {  // a flag
        if (option->count() > 1) throw cli::UsageError("option " + name + " given more than once");
        continue;
      }
      for (const std::string& value : option->results()) {
        if (value.empty()) throw cli::UsageError(name + " is given an empty value");
        if (name == "--model" && cli::is_builtin_model(value)) continue;  // (a body, not a file)
        if (value == "-" && among(inputs, name)) from_stdin.push_back(name);
        if (among(inputs, name) || among(outputs, name)) arguments.emplace_back(name, value);
      }
    }
  }
  if (from_stdin.size() > 1)
    throw cli::UsageError(
        fmt::format("{} both read standard input ('-'): only one may", fmt::join(from_stdin, " and ")));
  cli::check_command_line(std::move(arguments), outputs);
}

// The command and the subcommands its arguments name, in turn (motion, import).
std::vector<const CLI::App*> named_commands(const CLI::App& command, int argc, char** argv) {
  std::vector<const CLI::App*> apps = {&command};
  for (int k = 2; k < argc; ++k) {
    const std::string_view arg = argv[k];
    const auto sub = apps.back()->get_subcommands([&](const CLI::App* a) { return a->get_name() == arg; });
    if (!sub.empty()) apps.push_back(sub.front());
  }
  return apps;
}

// Before parsing: an option that takes a value followed by another of the command's options (`--out
// --floating`), which CLI11 would take as its value, so that the second option is lost; UsageError naming
// both. A value of that spelling is still given as `--out=--floating`.
void check_no_option_is_a_value(const CLI::App& command, int argc, char** argv) {
  namespace cli = humandyn::cli;
  // the options of the command and of the subcommands named (motion import)
  const std::vector<const CLI::App*> apps = named_commands(command, argc, argv);
  std::vector<const CLI::Option*> options;
  for (const CLI::App* app : apps)
    for (const CLI::Option* option : app->get_options()) options.push_back(option);
  // the option an argument names, a dash's or two's (a value such as -1 or a file name names none)
  const auto named = [&](std::string_view arg) -> const CLI::Option* {
    if (arg.size() < 2 || arg[0] != '-') return nullptr;
    const std::string name(arg.substr(0, arg.find('=')));
    const auto found = std::find_if(options.begin(), options.end(),
                                    [&](const CLI::Option* option) { return option->check_name(name); });
    return found == options.end() ? nullptr : *found;
  };
  for (int k = 1; k + 1 < argc; ++k) {
    const std::string_view arg = argv[k];
    if (arg == "--") return;
    const CLI::Option* option = arg.find('=') == std::string_view::npos ? named(arg) : nullptr;
    if (!option || option->get_expected_min() < 1) continue;
    if (named(argv[k + 1]))
      throw cli::UsageError(
          fmt::format("option {} needs a value, and {} that follows is an option (a value of that "
                      "spelling: {}={})",
                      arg, cli::shown(argv[k + 1]), arg, cli::shown(argv[k + 1])));
    ++k;  // (its value)
  }
}

// Prints a help text; exit code 1, with a message, when standard output does not take it.
int print_help(const std::string& text, const std::string& who) {
  if (std::fwrite(text.data(), 1, text.size(), stdout) == text.size() && std::fflush(stdout) == 0) return 0;
  humandyn::cli::print(stderr, "{}: {}\n", who, humandyn::cli::standard_output_failure());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  namespace cli = humandyn::cli;
  // a standard stream closed by the caller (2>&-) is opened again: else the first file the command opens
  // would take its descriptor, and a message meant for it would land in that file. Standard input and
  // error on /dev/null (nothing to read; messages lost, the exit code still tells), standard output on
  // /dev/full, where a result fails to be written, as the command's other outputs then are not
  for (int fd = 0; fd <= 2; ++fd) {
    if (!(::fcntl(fd, F_GETFD) == -1 && errno == EBADF)) continue;
    if (fd == 1) cli::standard_output_closed = true;
    if (fd == 2) cli::standard_error_closed = true;
    if (::open(fd == 1 ? "/dev/full" : "/dev/null", fd == 0 ? O_RDONLY : O_WRONLY) != fd &&
        ::open("/dev/null", fd == 0 ? O_RDONLY : O_WRONLY) != fd)  // (a system without /dev/full)
      return 1;
  }
  // every command of the table on one CLI::App, with the project's help layout
  CLI::App app("", "humandyn");
  app.formatter(std::make_shared<cli::HelpFormatter>());
  app.set_help_flag("--help", "this help");
  app.option_defaults()->group("options");
  app.require_subcommand(1);
  std::vector<cli::Command> commands;
  for (const auto add : cli::commands) {
    commands.push_back(add(app));
    for (CLI::App* sub : commands.back().app->get_subcommands([](CLI::App*) { return true; }))
      sub->get_option("--help")->group("options");  // (motion import, motion export)
    commands.back().app->get_option("--help")->group("options");
  }

  // `humandyn help [COMMAND]` as `humandyn [COMMAND] --help`
  const bool help = argc >= 2 && (std::string(argv[1]) == "help" || std::string(argv[1]) == "--help");
  if (argc < 2 || (help && (argc == 2 || std::string(argv[2]) == "help" || std::string(argv[2]) == "--help"))) {
    return print_help(app.help(), "humandyn");
  }
  const std::string name = argv[help ? 2 : 1];
  const auto chosen =
      std::find_if(commands.begin(), commands.end(), [&](const auto& c) { return c.app->get_name() == name; });
  if (chosen == commands.end()) {
    cli::print(stderr, "humandyn{}: unknown command '{}' (try `humandyn help`)\n", help ? " help" : "",
               cli::shown(name));
    return 2;
  }
  if (help) {  // `help motion import`: down the subcommands named
    CLI::App* asked = chosen->app;
    std::string prefix = "humandyn";  // as CLI11 calls help() for `motion import --help`
    for (int k = 3; k < argc; ++k) {
      const std::string sub = argv[k];
      const auto found = asked->get_subcommands([&](CLI::App* a) { return a->get_name() == sub; });
      if (found.empty()) {
        cli::print(stderr, "humandyn help: '{}' has no subcommand '{}'\n", asked->get_name(), cli::shown(sub));
        return 2;
      }
      prefix += " " + asked->get_name();
      asked = found.front();
    }
    return print_help(asked->help(prefix), "humandyn help");
  }

  // parse, run; every error is one line "humandyn <command>: ..." and an exit code: 2 for the user's, 1 for the input's
  const CLI::App& command = *chosen->app;
  // the command as given, down to `last` or to the innermost subcommand named (humandyn motion import)
  const std::vector<const CLI::App*> named = named_commands(command, argc, argv);
  const auto given = [&](const CLI::App* last = nullptr) {
    std::string text = "humandyn";
    for (const CLI::App* a : named) {
      text += " " + a->get_name();
      if (a == last) break;
    }
    return text;
  };
  const auto fail = [&](const std::string& message, int code, const CLI::App* last = nullptr) {
    cli::print(stderr, "{}: {}\n", given(last), message);
    return code;
  };
  try {
    check_no_option_is_a_value(command, argc, argv);
    app.parse(argc, argv);
    check_arguments(command);
    const int code = chosen->run();
    // what went to standard output reached it (a full disk, a closed descriptor: an error, not silence)
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) return fail(cli::standard_output_failure(), 1);
    return code;
  } catch (const CLI::CallForHelp&) {
    return print_help(command.help("humandyn"), given());
  } catch (const CLI::ParseError& e) {
    // the first subcommand given with an argument it did not take (`motion foo import`), else the
    // innermost (motion import)
    const CLI::App* used = &command;
    while (used->remaining().empty() && !used->get_subcommands().empty()) used = used->get_subcommands().front();
    return fail(cli::usage_message(e, *used), 2, used);
  } catch (const cli::UsageError& e) {
    return fail(e.what(), 2);
  } catch (const cli::InputError& e) {
    return fail(e.what(), 1);
  } catch (const humandyn::ModelError& e) {
    return fail(std::string("invalid model: ") + e.what(), 1);
  } catch (const std::system_error& e) {
    // fmt::print's failure to write standard output (a full disk, a closed descriptor), said as above
    if (std::string_view(e.what()).starts_with("cannot write to file"))
      return fail(cli::standard_output_closed ? cli::standard_output_failure()
                                              : fmt::format("standard output: writing failed: {}", e.code().message()),
                  1);
    return fail(e.what(), 1);
  } catch (const std::bad_alloc&) {
    // (an input too large for the memory: the outputs, written all or nothing, are not published)
    return fail("out of memory: the input needs more memory than the process can have", 1);
  } catch (const std::exception& e) {
    return fail(e.what(), 1);
  }
}
