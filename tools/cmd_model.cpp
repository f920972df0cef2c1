// humandyn model: prints a model, as a table to read or as JSON to rebuild it elsewhere.
#include "cli/atomic_file.hpp"
#include "cli/commands.hpp"
#include "cli/csv.hpp"
#include "cli/model_json.hpp"
#include "cli/model_source.hpp"
#include "cli/print.hpp"
#include "humandyn/model.hpp"
#include "text/shown.hpp"
#ifdef HUMANDYN_WITH_URDF
#include "humandyn/urdf.hpp"
#endif

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

namespace humandyn::cli {

namespace {

struct ModelCommandOptions {
  ModelOptions model;
  bool json = false;
  std::string urdf;  // "" for none
};

void print_table(const ModelDescription<double>& d, double total_mass, bool floating) {
  const auto& g = d.gravity;
  const auto& b = d.base_pose;
  fmt::print("model: {}{}\n", text::shown(d.name), floating ? "; floating base (free, 6-DOF) at the base link" : "");
  fmt::print(
      "{} joints, total mass {:.3f} kg; gravity ({:g}, {:g}, {:g}) m/s^2 in the world (z up, x forward, y left)\n",
      d.joints.size(), total_mass, g.x(), g.y(), g.z());
  fmt::print("base link {}: origin at ({:.4f}, {:.4f}, {:.4f}) m in the world{}, mass {:.3f} kg\n",
             text::shown(d.base_link_name), b.p.x(), b.p.y(), b.p.z(), floating ? " at the home state" : "",
             d.base_body.mass);
  fmt::print("  base rotation R (x_world = R x_base + p): [{:g} {:g} {:g}; {:g} {:g} {:g}; {:g} {:g} {:g}]\n",
             b.R(0, 0), b.R(0, 1), b.R(0, 2), b.R(1, 0), b.R(1, 1), b.R(1, 2), b.R(2, 0), b.R(2, 1), b.R(2, 2));
  fmt::print(
      "DH: T = Rz(theta + q) Tz(d) Tx(a) Rx(alpha), a and d in m, alpha and theta in degrees; centre of mass (m)\n"
      "and inertia about it (kg m^2) in the link frame\n\n");
  fmt::print(
      "{:>3}  {:<18} {:<18} {:<18} {:>8} {:>8} {:>7} {:>7} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} "
      "{:>8}\n",
      "#", "joint", "link", "parent", "a", "d", "alpha", "theta", "mass", "com x", "com y", "com z", "Ixx", "Iyy",
      "Izz", "Ixy", "Ixz", "Iyz");
  for (std::size_t i = 0; i < d.joints.size(); ++i) {
    const auto& j = d.joints[i];
    const std::string parent = j.parent < 0 ? "base" : d.joints[std::size_t(j.parent)].name;
    const auto& I = j.body.inertia;
    fmt::print(
        "{:3}  {:<18} {:<18} {:<18} {:8.4f} {:8.4f} {:7.1f} {:7.1f} {:8.3f} {:8.4f} {:8.4f} {:8.4f} {:8.4f} {:8.4f} "
        "{:8.4f} {:8.4f} {:8.4f} {:8.4f}\n",
        i + 1, j.name, text::shown(j.link_name), parent, j.dh.a, j.dh.d, j.dh.alpha * rad_to_deg,
        j.dh.theta * rad_to_deg, j.body.mass, j.body.com.x(), j.body.com.y(), j.body.com.z(), I(0, 0), I(1, 1), I(2, 2),
        I(0, 1), I(0, 2), I(1, 2));
    if (j.mounted) {
      const auto& m = j.mount;
      fmt::print(
          "     mount from the parent frame: p = ({:g}, {:g}, {:g}) m, R = [{:g} {:g} {:g}; {:g} {:g} {:g}; {:g} {:g} "
          "{:g}]\n",
          m.p.x(), m.p.y(), m.p.z(), m.R(0, 0), m.R(0, 1), m.R(0, 2), m.R(1, 0), m.R(1, 1), m.R(1, 2), m.R(2, 0),
          m.R(2, 1), m.R(2, 2));
    }
  }
  fmt::print("\n(# counts from 1 here; the JSON's indices and parents count from 0)\n");
}

#ifdef HUMANDYN_WITH_URDF
// What a URDF cannot carry of a model: gravity and the base's place in the world. The importer takes
// gravity in the base link's frame (--up, --gravity; default -9.81 along z) and builds the world from it
// alone: the base at the origin, the world's z against gravity. So the file `xml` is read back that way
// (before it is written: a document that does not read back is an error, and no file) and the warning
// returned ("" for none) says what to pass to keep gravity in the body and what else is lost.
std::string urdf_world_warning(const ModelDescription<double>& d, const std::string& xml, const std::string& model,
                               const std::string& file) {
  const Vec3<double> g = (d.base_pose.R.transpose() * d.gravity).array() + 0.0;  // no -0
  urdf::ImportOptions options;
  options.gravity = g;
  ModelDescription<double> back;
  try {
    back = urdf::import_urdf(xml, options, file).model;
  } catch (const std::exception& e) {
    throw InputError("model '" + shown(model) + "': its URDF does not read back, so " +
                     (file == "-" ? std::string("none is written") : shown(file) + " is not written") +
                     " (the lines are the document's): " + e.what());
  }
  const auto near = [](const auto& a, const auto& b) { return (a - b).norm() <= 1e-12 * (1 + b.norm()); };
  const bool default_gravity = near(g, Vec3<double>(0, 0, -9.81));
  const bool position = near(back.base_pose.p, d.base_pose.p);
  const bool orientation = near(back.base_pose.R, d.base_pose.R) && near(back.gravity, d.gravity);
  if (default_gravity && position && orientation) return "";

  std::string how = "--gravity " + format_number(g.x()) + "," + format_number(g.y()) + "," + format_number(g.z());
  for (int k = 0; k < 3; ++k)
    if (std::abs(std::abs(g[k]) - 9.81) < 1e-12 && std::abs(g[(k + 1) % 3]) + std::abs(g[(k + 2) % 3]) < 1e-12)
      how = std::string("--up ") + (g[k] < 0 ? "" : "-") + "xyz"[k];
  const Vec3<double>& p = d.base_pose.p;
  std::string lost;
  if (!position)
    lost += "; the base's position in the world, (" + format_number(p.x()) + ", " + format_number(p.y()) + ", " +
            format_number(p.z()) + ") m, is not kept: read back, its origin is the world's";
  if (!orientation)
    lost +=
        "; the base's orientation in the world is not kept: read back, the world's axes are built from "
        "gravity alone (z against it)";
  return fmt::format(
      "humandyn model: warning: {} has no place for the gravity or the base pose of '{}': gravity in its "
      "base link's frame, ({}, {}, {}) m/s^2, is in its first comment{}{}\n",
      file == "-" ? std::string("the URDF on standard output") : shown(file), shown(model), format_number(g.x()),
      format_number(g.y()), format_number(g.z()), default_gravity ? "" : "; read it back with " + how + " to keep it",
      lost);
}
#endif

int run_model(const ModelCommandOptions& o) {
  // the model is printed whatever else is written: with standard output closed, nothing is (not a URDF
  // file that a failed run would have replaced)
  if (standard_output_closed) throw InputError(standard_output_failure());
  // a model file's "landmarks" go through to its JSON unchanged; a URDF has no place for them, which is said
  std::optional<json::Json> landmarks;
  const ModelDescription<double> description = load_model(o.model, &landmarks);
#ifndef HUMANDYN_WITH_URDF
  if (!o.urdf.empty()) throw UsageError("--urdf: this build has no URDF support (HUMANDYN_BUILD_URDF=OFF)");
#endif

  // validate before writing or printing: what comes out is a model the library accepts
  const AnyModel<double> model(description);
#ifdef HUMANDYN_WITH_URDF
  if (!o.urdf.empty()) {
    if (o.model.floating) throw UsageError("--urdf writes the stance-rooted form, not --floating");
    const std::string xml = urdf::to_urdf(description);
    const std::string warning = urdf_world_warning(description, xml, o.model.model, o.urdf);
    write_file_atomically(o.urdf, xml);
    std::fputs(warning.c_str(), stderr);
    if (landmarks)
      cli::print(stderr, "humandyn model: warning: {}'s \"landmarks\" are not in {}: a URDF has no place for them\n",
                 o.model.model, o.urdf);
  }
#endif
  if (o.json) {
    json::Json doc = model_to_json(description, o.model.floating);
    if (landmarks) doc["landmarks"] = *landmarks;
    std::fputs(json::write(doc).c_str(), stdout);
  } else {
    print_table(description, model.total_mass(), o.model.floating);
  }
  return std::fflush(stdout) == 0 ? 0 : 1;
}

}  // namespace

Command add_model(CLI::App& humandyn) {
  const auto o = std::make_shared<ModelCommandOptions>();
  CLI::App* c = humandyn.add_subcommand(
      "model",
      "print a model (joints, DH rows, masses, inertias) as a table or as JSON\n\n"
      "Prints the model: for each joint its parent, DH row (T = Rz(theta+q) Tz(d) Tx(a) Rx(alpha)), optional\n"
      "mount, and its link's mass, centre of mass and inertia about the centre of mass in the link frame;\n"
      "gravity and the base pose.");
  add_model_options(*c, o->model);
  add_floating_option(*c, o->model,
                      "Its JSON says so (\"base\": {\"joint\": \"floating\"}) and states\n"
                      "the floating state's conventions, so that another library can rebuild\n"
                      "it with a free-flyer base");
  c->add_flag("--json", o->json, "JSON with the conventions stated inside; `--model FILE.json` reads it\nback");
  c->add_option("--urdf", o->urdf,
                "also write the model as a URDF file (continuous joints, DH frames as\ntip links; '-': standard "
                "output, before the table or the JSON)")
      ->option_text("OUT");
  return {c, [o] { return run_model(*o); }};
}

}  // namespace humandyn::cli
