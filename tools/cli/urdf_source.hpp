// A URDF file as a model on the command line: `FILE.urdf [--root LINK] [--joints MAP] [--up AXIS |
// --gravity GX,GY,GZ] [--balance-inertia]`, shared by `--model FILE.urdf` and `humandyn urdf2dh`.
#pragma once

#include "cli/errors.hpp"
#include "cli/options.hpp"

#ifdef HUMANDYN_WITH_URDF
#include "humandyn/urdf.hpp"
#endif

#include <CLI/CLI.hpp>
#include <Eigen/Core>

#include <optional>
#include <string>

namespace humandyn::cli {

// Whether `name` names a URDF file (ends in .urdf, in any case).
inline bool is_urdf_path(const std::string& name) { return has_ending(name, ".urdf"); }

// The importer's options as given.
struct UrdfOptions {
  std::string root, joints, up;
  std::optional<Eigen::Vector3d> gravity;
  bool balance_inertia = false;
  bool given() const { return !root.empty() || !joints.empty() || !up.empty() || gravity || balance_inertia; }
};

#ifdef HUMANDYN_WITH_URDF
// Registers --root, --joints, --up, --gravity and --balance-inertia on `command`, in the option group `group`;
// without `world`, not --up and --gravity (motion import: the clip gives the world's up, and the body the fit
// takes is built from the file's lengths).
void add_urdf_options(CLI::App& command, UrdfOptions& options, const std::string& group, bool world = true);

// Imports `path` with the importer's options; InputError for a bad file or joint map, UsageError for a bad option.
urdf::Import import_urdf(const std::string& path, const UrdfOptions& options);
#endif

}  // namespace humandyn::cli
