// humandyn: the command line. `humandyn <command> [options]`; `humandyn help` lists the commands.
#include "cli/commands.hpp"
#include "humandyn/model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <memory>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  namespace cli = humandyn::cli;
  // every command of the table on one CLI::App, with the project's help layout
  CLI::App app("", "humandyn");
  app.formatter(std::make_shared<cli::HelpFormatter>());
  app.set_help_flag("--help", "this help");
  app.option_defaults()->group("options");
  app.require_subcommand(1);
  std::vector<cli::Command> commands;
  for (const auto add : cli::commands) {
    commands.push_back(add(app));
    commands.back().app->get_option("--help")->group("options");
  }

  if (argc < 2 || std::string(argv[1]) == "help" || std::string(argv[1]) == "--help") {
    fmt::print("{}", app.help());
    return 0;
  }
  const std::string name = argv[1];
  const auto chosen =
      std::find_if(commands.begin(), commands.end(), [&](const auto& c) { return c.app->get_name() == name; });
  if (chosen == commands.end()) {
    fmt::print(stderr, "humandyn: unknown command '{}' (try `humandyn help`)\n", name);
    return 2;
  }

  // parse, run; every error is one line "humandyn <command>: ..." and an exit code: 2 for the user's, 1 for the input's
  const CLI::App& command = *chosen->app;
  const auto fail = [&](const std::string& message, int code) {
    fmt::print(stderr, "humandyn {}: {}\n", name, message);
    return code;
  };
  try {
    app.parse(argc, argv);
    return chosen->run();
  } catch (const CLI::CallForHelp&) {
    fmt::print("{}", command.help("humandyn"));
    return 0;
  } catch (const CLI::ParseError& e) {
    return fail(cli::usage_message(e, command), 2);
  } catch (const cli::UsageError& e) {
    return fail(e.what(), 2);
  } catch (const cli::InputError& e) {
    return fail(e.what(), 1);
  } catch (const humandyn::ModelError& e) {
    return fail(std::string("invalid model: ") + e.what(), 1);
  } catch (const std::exception& e) {
    return fail(e.what(), 1);
  }
}
