// humandyn urdf2dh: a URDF file as DH chains, the table of every chain (or the model as JSON).
#include "cli/commands.hpp"
#include "cli/model_json.hpp"
#include "cli/urdf_source.hpp"
#include "humandyn/model.hpp"
#include "humandyn/shape.hpp"
#include "humandyn/urdf.hpp"
#include "text/shown.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace humandyn::cli {

namespace {

// round-off below the printed digits shown as 0, not -0
double clean(double v) { return std::abs(v) < 5e-13 ? 0.0 : v; }

struct Urdf2dhOptions {
  std::string file;
  UrdfOptions urdf;
  bool json = false;
};

// the characters of UTF-8 text (its bytes less the continuation bytes), and the text padded with blanks to
// `width` of them
std::size_t characters(const std::string& s) {
  return std::size_t(
      std::count_if(s.begin(), s.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}
std::string padded(const std::string& s, std::size_t width) {
  return s + std::string(width - std::min(width, characters(s)), ' ');
}

const char* twist_name(Twist t) {
  switch (t) {
    case Twist::Zero:
      return "0";
    case Twist::HalfPi:
      return "+90";
    case Twist::MinusHalfPi:
      return "-90";
    case Twist::Pi:
      return "180";
    default:
      return "general";
  }
}

void print_chains(const urdf::Import& imp) {
  const auto& d = imp.model;
  const int n = int(d.joints.size());
  std::vector<int> parent(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) parent[std::size_t(i)] = d.joints[std::size_t(i)].parent;
  std::vector<ChainSpec> chains(std::size_t(count_chains(parent, n)));
  split_chains(parent, n, chains);
  double mass = d.base_body.mass;
  for (const auto& j : d.joints) mass += j.body.mass;
  fmt::print("robot: {}\nbase link {}; {} joints in {} chains; total mass {:.4f} kg\n", text::shown(d.name),
             text::shown(d.base_link_name), n, chains.size(), mass);
  const Eigen::Vector3d g = d.base_pose.R.transpose() * d.gravity;
  fmt::print("gravity in the base link's frame: ({:g}, {:g}, {:g}) m/s^2\n", g.x(), g.y(), g.z());
  fmt::print("DH: a and d in m, alpha and theta in degrees; 'rev' marks a joint reversed by re-rooting\n");
  // the name columns as wide as the longest name (22 characters at least), so that the numbers line up
  std::size_t joint_width = 22, link_width = 22;
  for (const auto& j : d.joints) {
    joint_width = std::max(joint_width, characters(text::shown(j.name)));
    link_width = std::max(link_width, characters(text::shown(j.link_name)));
  }
  for (std::size_t c = 0; c < chains.size(); ++c) {
    const auto& ch = chains[c];
    const std::string from = ch.parent < 0 ? "base " + text::shown(d.base_link_name)
                                           : "link " + text::shown(d.joints[std::size_t(ch.parent)].link_name) +
                                                 " (joint " + std::to_string(ch.parent + 1) + ")";
    fmt::print("\nchain {}, from {}:\n", c + 1, from);
    fmt::print("{:>4}  {} {} {:>3} {:>10} {:>10} {:>10} {:>10} {:>8} {:>9}\n", "#", padded("joint", joint_width),
               padded("link", link_width), "", "a", "alpha", "d", "theta", "twist", "mass");
    for (int i = ch.first; i < ch.first + ch.length; ++i) {
      const auto& j = d.joints[std::size_t(i)];
      fmt::print("{:4}  {} {} {:>3} {:10.6f} {:10.4f} {:10.6f} {:10.4f} {:>8} {:9.4f}\n", i + 1,
                 padded(text::shown(j.name), joint_width), padded(text::shown(j.link_name), link_width),
                 imp.reversed[std::size_t(i)] ? "rev" : "", clean(j.dh.a), clean(j.dh.alpha * rad_to_deg),
                 clean(j.dh.d), clean(j.dh.theta * rad_to_deg), twist_name(classify_twist(j.dh.alpha)), j.body.mass);
      if (j.mounted) {
        const auto& m = j.mount;
        fmt::print(
            "      mount: p = ({:.6f}, {:.6f}, {:.6f}) m, R = [{:.6f} {:.6f} {:.6f}; {:.6f} {:.6f} {:.6f}; {:.6f} "
            "{:.6f} {:.6f}]\n",
            clean(m.p.x()), clean(m.p.y()), clean(m.p.z()), clean(m.R(0, 0)), clean(m.R(0, 1)), clean(m.R(0, 2)),
            clean(m.R(1, 0)), clean(m.R(1, 1)), clean(m.R(1, 2)), clean(m.R(2, 0)), clean(m.R(2, 1)), clean(m.R(2, 2)));
      }
      if (imp.urdf_joints[std::size_t(i)] != j.name)
        fmt::print("      URDF joint: {}\n", imp.urdf_joints[std::size_t(i)]);
    }
  }
  std::string why;
  if (urdf::try_human_model(d, &why))
    fmt::print("\nthe model has the seed's shape: it also runs as a HumanModel (compile-time shape)\n");
}

int run_urdf2dh(const Urdf2dhOptions& o) {
  const urdf::Import imp = import_urdf(o.file, o.urdf);
  if (o.json)
    std::fputs(write_model_json(imp.model).c_str(), stdout);
  else
    print_chains(imp);
  return std::fflush(stdout) == 0 ? 0 : 1;
}

}  // namespace

Command add_urdf2dh(CLI::App& humandyn) {
  const auto o = std::make_shared<Urdf2dhOptions>();
  CLI::App* c = humandyn.add_subcommand(
      "urdf2dh",
      "a URDF file as DH chains: the table of every chain, or --json\n\n"
      "Imports a URDF tree as chains of standard DH links, T = Rz(theta+q) Tz(d) Tx(a) Rx(alpha), and prints\n"
      "the DH table of every chain (a chain starts at the base or at a branch point). Fixed and locked\n"
      "joints are merged into rigid links; a mount is the fixed frame a chain needs where it leaves its\n"
      "parent link off that link's z axis. Joints keep their URDF names (or the joint map's).");
  c->add_option("FILE.urdf", o->file, "the URDF file")->required();
  add_urdf_options(*c, o->urdf, "options");
  c->add_flag("--json", o->json, "the model in the format of `humandyn model --json`");
  return {c, [o] { return run_urdf2dh(*o); }};
}

}  // namespace humandyn::cli
