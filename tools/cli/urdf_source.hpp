// A URDF file as a model on the command line: `FILE.urdf [--root LINK] [--joints MAP] [--up AXIS |
// --gravity GX,GY,GZ] [--balance-inertia]`, shared by `--model FILE.urdf` and `humandyn urdf2dh`.
#pragma once

#include "cli/args.hpp"

#ifdef HUMANDYN_WITH_URDF
#include "humandyn/urdf.hpp"
#endif

#include <set>
#include <string>

namespace humandyn::cli {

// Whether `name` names a URDF file (ends in .urdf).
inline bool is_urdf_path(const std::string& name) {
  return name.size() > 5 && name.compare(name.size() - 5, 5, ".urdf") == 0;
}

#ifdef HUMANDYN_WITH_URDF
// Reads the importer's options from `args` and imports `path`; InputError for a bad file or joint map,
// UsageError for a bad option.
urdf::Import import_urdf_args(Args& args, const std::string& path);
#endif

// The importer's options that take no value, accepted by every command (main.cpp adds them to each
// command's flags).
inline const std::set<std::string> urdf_flags{};

// The options help texts list.
inline constexpr const char* urdf_options_help =
    "  --root LINK      the base link (default: the URDF's root); the joints on the way are reversed\n"
    "  --joints MAP     joint map: which URDF joints become model joints, the others locked (docs/urdf.md)\n"
    "  --up AXIS        the world's up axis in the base link's frame: x, y, z, -x, -y, -z (default z)\n"
    "  --gravity G      or the gravity vector in the base link's frame, GX,GY,GZ in m/s^2\n"
    "  --balance-inertia  a link whose principal moments violate the triangle inequality gets their mean\n"
    "                   (MuJoCo's balanceinertia) instead of an error; each change is printed on stderr\n";

}  // namespace humandyn::cli
