// Where a subcommand's model comes from: `--model default|female|paper` (built in), `--model FILE.json`
// (the format of `humandyn model --json`, cli/model_json.hpp) or, once the URDF
// importer is built in, `--model FILE.urdf [--root LINK] [--joints MAP] [--up AXIS]`; and, on the
// commands that take it, `--floating`: the floating form of that body (floating.hpp: a free base at the
// pelvis), or a FILE.json of the floating form as `humandyn model --json --floating` writes it.
#pragma once

#include "cli/json.hpp"
#include "cli/urdf_source.hpp"
#include "humandyn/model.hpp"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace humandyn::cli {

struct ModelOptions {
  std::string model = "default";
  UrdfOptions urdf;               // with a FILE.urdf only
  bool floating = false;          // --floating
  bool floating_offered = false;  // whether the command has --floating (add_floating_option)
};

// Registers --model and the URDF importer's options on `command`, in the option group "the model".
CLI::Option* add_model_options(CLI::App& command, ModelOptions& options);

// Registers --floating (in the same group); `effect` ends its help (what the floating form changes there).
CLI::Option* add_floating_option(CLI::App& command, ModelOptions& options, const std::string& effect);

// The model as --model gives it, read once: its description (the floating form when a model file says
// so: `floating` set) and a model file's "landmarks" (`motion import --model-out` writes them;
// model_from_json checks their form). UsageError or InputError on bad input.
struct ModelSource {
  ModelDescription<double> description;
  bool floating = false;
  std::optional<json::Json> landmarks;
};
ModelSource read_model(const ModelOptions& options);

// Whether `--model NAME` names a built-in body (one of builtin_model_names), which is no file.
bool is_builtin_model(const std::string& name);

// The built-in bodies' names, joined by `separator`, the last by `last` ("default, female or paper").
std::string builtin_model_names(const std::string& separator, const std::string& last);

// The model description the options name, in the floating form with --floating; UsageError or
// InputError on bad input (a floating model file without --floating, a body --floating cannot re-root).
// `landmarks`, when given, receives a model file's "landmarks".
ModelDescription<double> load_model(const ModelOptions& options, std::optional<json::Json>* landmarks = nullptr);

// The smallest pivot below this fraction of the largest marks a singular mass matrix: round-off of a
// zero pivot sits near 1e-16 of the largest, a light hand's real pivot near 1e-7.
inline constexpr double singular_pivot = 1e-10;

// The joint at which a mass matrix is singular, as check_pivots finds it, or -1 where it is regular.
Eigen::Index singular_joint(const Eigen::VectorXd& pivots);

// Refuses a singular mass matrix: its pivots (the articulated inertia about each joint axis, or D of
// M = L^T D L) looked at in the order the elimination meets them, tips inwards; the first that is not
// clearly positive is where M is singular (a zero pivot turns those after it into NaN). InputError
// starting with `where`, naming the joint.
void check_pivots(const Eigen::VectorXd& pivots, const AnyModel<double>& model, const std::string& where);

// The floating form's whole mass matrix [Mbb Mbj; Mbj^T M] at q (6 + nj square), singular where a motion
// of the base with the joints moves no mass although each joint alone moves some (the paper model's
// massless pelvis: the base turning about the line of its three joints as they turn back). Scaled by its
// diagonal, so that the base's units and the joints' weigh alike, its smallest eigenvalue at most
// singular_pivot of the largest marks it. Returns "" where it is regular, or where a joint alone moves
// no mass (check_pivots names that joint); else the motion, in words: "turning the base with joints 'a',
// 'b'" (those whose part of the scaled motion is at least a tenth of its largest) or "a motion of the base
// alone". Allocates (a command's check).
std::string floating_null_motion(const AnyModel<double>& model, const Eigen::VectorXd& q);

// Refuses a model whose mass matrix is singular at the home pose (every angle 0), as check_pivots.
void check_mass_matrix_at_home(const AnyModel<double>& model);

}  // namespace humandyn::cli
