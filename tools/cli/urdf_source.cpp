#include "cli/urdf_source.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace humandyn::cli {

urdf::Import import_urdf_args(Args& args, const std::string& path) {
  urdf::ImportOptions options;
  options.root = args.get_or("--root", "");
  options.balance_inertia = args.flag("--balance-inertia");
  const auto up = args.get("--up");
  const auto gravity = args.get("--gravity");
  if (up && gravity) throw UsageError("give --up or --gravity, not both");
  if (up) {
    try {
      options.gravity = urdf::gravity_for_up(*up);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--up: ") + e.what());
    }
  }
  if (gravity) {
    std::string text = *gravity;
    for (auto& c : text)
      if (c == ',') c = ' ';
    std::istringstream in(text);
    double g[3];
    std::string rest;
    if (!(in >> g[0] >> g[1] >> g[2]) || (in >> rest) || !std::isfinite(g[0] + g[1] + g[2]))
      throw UsageError("--gravity needs three finite numbers GX,GY,GZ, got '" + *gravity + "'");
    options.gravity = Eigen::Vector3d(g[0], g[1], g[2]);
  }
  try {
    if (const auto map = args.get("--joints")) options.joints = urdf::read_joint_map(*map);
    urdf::Import imp = urdf::import_urdf_file(path, options);
    for (const auto& w : imp.warnings) std::fprintf(stderr, "humandyn: warning: %s\n", w.c_str());
    return imp;
  } catch (const urdf::Error& e) {
    throw InputError(e.what());
  }
}

}  // namespace humandyn::cli
