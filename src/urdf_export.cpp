// A model description as a URDF document. Each model link becomes a URDF link whose frame sits on its
// joint's axis and turns with it, Z_i = B_i Rz(theta_i + q_i) (B_i: the joint's frame, the parent's DH
// frame after its mount); the DH frame is then D_i = Z_i Tz(d_i) Tx(a_i) Rx(alpha_i), so Z_i and D_i
// share their x axis. The joint's origin in its parent link is E_p * mount_i * Rz(theta_i), with
// E_p = Tz(d_p) Tx(a_p) Rx(alpha_p) (identity for the base), and its axis is z. A chain's last link
// gets a fixed "<link>_tip" frame at its DH frame. The importer's conventions (docs/urdf.md) then
// rebuild the same DH frames from this file.
#include "humandyn/urdf.hpp"
#include "text/names.hpp"
#include "text/shown.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

namespace humandyn::urdf {

namespace {

using Eigen::Vector3d;
using P = Pose<double>;

std::string num(double v) {
  if (v == 0) return "0";  // no "-0"
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// A name as XML attribute text; Error for a name the names' rule refuses (text::label_fault: a control
// character other than tab, line feed and carriage return, U+FFFE, U+FFFF, a byte that is not UTF-8: what
// XML cannot carry, or only as a discouraged character). An empty name is written empty.
std::string escape(const std::string& s) {
  if (const std::string fault = s.empty() ? "" : text::label_fault(s); !fault.empty())
    throw Error("'" + text::shown(s) + "' cannot be written into a URDF: " + fault);
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      case '\t':
      case '\n':
      case '\r':  // kept by a character reference (an attribute's reader turns them into blanks)
        out += "&#" + std::to_string(int(c)) + ";";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// URDF's roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll).
Vector3d rpy(const Eigen::Matrix3d& R) {
  const double cp = std::hypot(R(0, 0), R(1, 0));
  const double pitch = std::atan2(-R(2, 0), cp);
  if (cp < 1e-12) return Vector3d(std::atan2(-R(1, 2), R(1, 1)), pitch, 0);  // gimbal lock: yaw folded into roll
  return Vector3d(std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0)));
}

std::string origin(const P& X) {
  const Vector3d r = rpy(X.R);
  return "<origin xyz=\"" + num(X.p.x()) + " " + num(X.p.y()) + " " + num(X.p.z()) + "\" rpy=\"" + num(r.x()) + " " +
         num(r.y()) + " " + num(r.z()) + "\"/>";
}

void inertial(std::ostringstream& out, const RigidBodyInertia<double>& b) {
  if (b.mass == 0 && b.inertia.isZero()) return;
  const auto& I = b.inertia;
  out << "    <inertial>\n      " << origin(P{Eigen::Matrix3d::Identity(), b.com}) << "\n      <mass value=\""
      << num(b.mass) << "\"/>\n      <inertia ixx=\"" << num(I(0, 0)) << "\" ixy=\"" << num(I(0, 1)) << "\" ixz=\""
      << num(I(0, 2)) << "\" iyy=\"" << num(I(1, 1)) << "\" iyz=\"" << num(I(1, 2)) << "\" izz=\"" << num(I(2, 2))
      << "\"/>\n    </inertial>\n";
}

P rot_z(double theta) {
  P X;
  X.R = Eigen::AngleAxisd(theta, Vector3d::UnitZ()).toRotationMatrix();
  return X;
}

// E = Tz(d) Tx(a) Rx(alpha): the DH frame in the joint-axis link frame
P dh_tail(const DHParameters<double>& dh) {
  P X;
  X.R = Eigen::AngleAxisd(dh.alpha, Vector3d::UnitX()).toRotationMatrix();
  X.p = Vector3d(dh.a, 0, dh.d);
  return X;
}

}  // namespace

std::string to_urdf(const ModelDescription<double>& d) {
  const Model<double, DynamicShape> checked(d);  // validates the description
  (void)checked;
  const int n = int(d.joints.size());

  // unique link names: the model's where they are unique and not empty; the tips' fixed joints are named
  // after their chain's last joint (so they follow the joint names' rule) and kept apart from every joint
  std::set<std::string> used, used_joints;
  const auto unique_in = [](std::set<std::string>& names, std::string name, const std::string& fallback) {
    if (name.empty() || names.count(name)) name = fallback;
    while (names.count(name)) name += "_";
    names.insert(name);
    return name;
  };
  const auto unique = [&](const std::string& name, const std::string& fallback) {
    return unique_in(used, name, fallback);
  };
  for (const auto& j : d.joints) used_joints.insert(j.name);
  const std::string base = unique(d.base_link_name, "base");
  std::vector<std::string> link(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    link[std::size_t(i)] = unique(d.joints[std::size_t(i)].link_name, "link_" + std::to_string(i + 1));
  std::vector<bool> leaf(static_cast<std::size_t>(n), true);
  for (const auto& j : d.joints)
    if (j.parent >= 0) leaf[std::size_t(j.parent)] = false;

  std::ostringstream out;
  const Vector3d g = d.base_pose.R.transpose() * d.gravity;
  // (the model's name only in the robot's attribute: a comment may hold no "--", which a name may)
  out << "<?xml version=\"1.0\"?>\n<!-- " << n << " revolute joints, standard DH frames on the"
      << " chains; gravity in the base link frame: " << num(g.x()) << " " << num(g.y()) << " " << num(g.z())
      << " m/s^2 -->\n<robot name=\"" << escape(d.name) << "\">\n";
  out << "  <link name=\"" << escape(base) << "\">\n";
  inertial(out, d.base_body);
  out << "  </link>\n";
  for (int i = 0; i < n; ++i) {
    const auto& j = d.joints[std::size_t(i)];
    const P E = dh_tail(j.dh);
    const P Ep = j.parent < 0 ? P{} : dh_tail(d.joints[std::size_t(j.parent)].dh);
    const P mount = j.mounted ? j.mount : P{};
    // the link, its inertia moved from the DH frame to the joint-axis frame
    RigidBodyInertia<double> b = j.body;
    b.com = E * j.body.com;
    b.inertia = E.R * j.body.inertia * E.R.transpose();
    b.inertia = 0.5 * (b.inertia + b.inertia.transpose()).eval();
    out << "  <link name=\"" << escape(link[std::size_t(i)]) << "\">\n";
    inertial(out, b);
    out << "  </link>\n";
    out << "  <joint name=\"" << escape(j.name) << "\" type=\"continuous\">\n    <parent link=\""
        << escape(j.parent < 0 ? base : link[std::size_t(j.parent)]) << "\"/>\n    <child link=\""
        << escape(link[std::size_t(i)]) << "\"/>\n    " << origin(Ep * mount * rot_z(j.dh.theta))
        << "\n    <axis xyz=\"0 0 1\"/>\n  </joint>\n";
    if (leaf[std::size_t(i)]) {
      const std::string tip = unique(link[std::size_t(i)] + "_tip", link[std::size_t(i)] + "_tip");
      const std::string tip_joint = unique_in(used_joints, j.name + "_tip", j.name + "_tip");
      out << "  <link name=\"" << escape(tip) << "\"/>\n  <joint name=\"" << escape(tip_joint) << "\" type=\"fixed\">\n"
          << "    <parent link=\"" << escape(link[std::size_t(i)]) << "\"/>\n    <child link=\"" << escape(tip)
          << "\"/>\n    " << origin(E) << "\n  </joint>\n";
    }
  }
  out << "</robot>\n";
  return out.str();
}

std::optional<HumanModel<double>> try_human_model(const ModelDescription<double>& description, std::string* why) {
  try {
    return HumanModel<double>(description);
  } catch (const ModelError& e) {
    if (why) *why = e.what();
    return std::nullopt;
  }
}

}  // namespace humandyn::urdf
