#include "cli/urdf_source.hpp"

#include "cli/options.hpp"
#include "cli/print.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace humandyn::cli {

void add_urdf_options(CLI::App& command, UrdfOptions& options, const std::string& group, bool world) {
  command
      .add_option("--root", options.root,
                  "the base link (default: the URDF's root); the joints on the way are\nreversed")
      ->option_text("LINK")
      ->group(group);
  command
      .add_option("--joints", options.joints,
                  "joint map: which URDF joints become model joints, the others locked\n(docs/urdf.md)")
      ->option_text("MAP")
      ->group(group);
  if (world) {
    CLI::Option* up = command
                          .add_option_function<std::string>(
                              "--up",
                              [&options](const std::string& text) {
                                // checked here: an empty axis would read as the option left out
                                try {
                                  urdf::gravity_for_up(text);
                                } catch (const std::invalid_argument& e) {
                                  throw UsageError(std::string("--up: ") + e.what());
                                }
                                options.up = text;
                              },
                              "the world's up axis in the base link's frame: x, y, z, -x, -y, -z\n(default z)")
                          ->option_text("AXIS")
                          ->group(group);
    command
        .add_option_function<std::string>(
            "--gravity",
            [&options](const std::string& text) {
              double g[3];
              if (std::string why; !read_numbers(text, g, 3, &why))
                throw UsageError("--gravity needs three finite numbers GX,GY,GZ, got '" + shown(text) + "': " + why);
              options.gravity = Eigen::Vector3d(g[0], g[1], g[2]);
              // stableNorm: no overflow for components near 1e155
              const double magnitude = options.gravity->stableNorm();
              if (!std::isfinite(magnitude))
                throw UsageError("--gravity: the vector's magnitude overflows a double (above 1.8e308), got '" +
                                 shown(text) + "'");
              if (magnitude > max_description_gravity)
                throw UsageError(
                    fmt::format("--gravity '{}': the vector's magnitude, {:.9g} m/s^2, is beyond {:.9g} "
                                "m/s^2 (a model's largest gravity)",
                                shown(text), magnitude, max_description_gravity));
            },
            "or the gravity vector in the base link's frame, GX,GY,GZ in m/s^2")
        ->option_text("G")
        ->group(group)
        ->excludes(up);
  }
  command
      .add_flag("--balance-inertia", options.balance_inertia,
                "a link whose principal moments violate the triangle inequality gets\n"
                "their mean (MuJoCo's balanceinertia) instead of an error; each change\nis printed on stderr")
      ->group(group);
}

urdf::Import import_urdf(const std::string& path, const UrdfOptions& options) {
  urdf::ImportOptions import;
  import.root = options.root;
  import.balance_inertia = options.balance_inertia;
  if (!options.up.empty()) {
    try {
      import.gravity = urdf::gravity_for_up(options.up);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--up: ") + e.what());
    }
  }
  if (options.gravity) import.gravity = *options.gravity;
  try {
    if (!options.joints.empty()) import.joints = urdf::read_joint_map(options.joints);
    urdf::Import imp = urdf::import_urdf_file(path, import);
    for (const auto& w : imp.warnings) cli::print(stderr, "humandyn: warning: {}\n", w);
    return imp;
  } catch (const urdf::Error& e) {
    throw InputError(e.what());
  }
}

}  // namespace humandyn::cli
