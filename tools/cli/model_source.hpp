// Where a subcommand's model comes from: `--model default|female|paper` (built in), `--model FILE.json`
// (the format of `humandyn model --json`, cli/model_json.hpp) or, once the URDF
// importer is built in, `--model FILE.urdf [--root LINK] [--joints MAP] [--up AXIS]`.
#pragma once

#include "cli/urdf_source.hpp"
#include "humandyn/model.hpp"

#include <CLI/CLI.hpp>

#include <string>

namespace humandyn::cli {

struct ModelOptions {
  std::string model = "default";
  UrdfOptions urdf;  // with a FILE.urdf only
};

// Registers --model and the URDF importer's options on `command`, in the option group "the model".
CLI::Option* add_model_options(CLI::App& command, ModelOptions& options);

// The model description the options name; UsageError or InputError on bad input.
ModelDescription<double> load_model(const ModelOptions& options);

}  // namespace humandyn::cli
