// Where a subcommand's model comes from: `--model default|female|paper` (built in), `--model FILE.json`
// (the format of `humandyn model --json`, cli/model_json.hpp) or, once the URDF
// importer is built in, `--model FILE.urdf [--root LINK] [--joints MAP] [--up AXIS]`.
#pragma once

#include "cli/args.hpp"
#include "humandyn/model.hpp"

#include <string>

namespace humandyn::cli {

// Reads --model (and the options that go with it) and returns the model description; UsageError
// or InputError on bad input.
ModelDescription<double> load_model(Args& args);

// The built-in model names, for help texts.
inline constexpr const char* builtin_models = "default|female|paper";

// The help of --model and of the importer's options that go with a URDF file, for every command's --help.
std::string model_options_help();

}  // namespace humandyn::cli
