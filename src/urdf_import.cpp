// URDF tree -> rigid bodies -> re-rooted tree of revolute joints -> DH chains.
//
// 1. Bodies. Fixed joints and locked joints glue links into rigid bodies; the remaining (model) joints
//    connect bodies. Each body has a reference frame, the URDF frame of its anchor link: the base link
//    for the base body, otherwise the link on the body's side of the joint that moves it.
// 2. Re-rooting. The body tree is walked from the base body. A joint walked from its URDF child to its
//    URDF parent is reversed: with X_CP(q) = Rot(-axis, q) * origin^-1, it turns about the same line in
//    the opposite sense, so its angle q (and torque) keep their URDF meaning.
// 3. DH frames (standard DH). Each joint's axis is a line fixed in its parent body. The DH frame D_j of
//    body j has its z axis on the axis of its first child joint and its x axis on the common normal
//    of its own axis and that child's (docs/urdf.md lists the degenerate cases). Every other child
//    either turns about D_j's z axis (no mount) or gets a mount: a fixed frame on its axis.
// 4. Inertias: every link's inertial is moved into its body's DH frame and the body's links lumped.
#include "urdf_document.hpp"

#include "humandyn/urdf.hpp"
#include "text/file.hpp"
#include "text/shown.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

namespace humandyn::urdf {

using detail::JointType;
using detail::UrdfDocument;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using P = Pose<double>;

namespace {

// Geometric tolerances: axes are parallel when the sine of their angle is below kParallel, lines
// meet when they pass closer than kMeet metres.
constexpr double kParallel = 1e-9;
constexpr double kMeet = 1e-9;
// Nearly parallel axes put their common normal far away, and a DH row there would carry huge d offsets
// (and lose precision): beyond kFar metres from the joints' origins a mount is used instead.
constexpr double kFar = 10.0;

[[noreturn]] void fail(const std::string& message) { throw Error(message); }

P rotation_about(const Vector3d& axis, double angle) {
  P X;
  X.R = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  return X;
}

// A line fixed in a body: a point and a unit direction.
struct Line {
  Vector3d o, u;
};

Line transform(const P& X, const Line& L) { return {X * L.o, X.R * L.u}; }

// A unit vector perpendicular to u: the first of the hints that is not parallel to u, projected.
Vector3d perpendicular(const Vector3d& u, std::initializer_list<Vector3d> hints) {
  for (const auto& h : hints) {
    const Vector3d x = h - h.dot(u) * u;
    if (x.norm() > 1e-6) return x.normalized();
  }
  const Vector3d x = Vector3d::UnitX() - u.x() * u;  // never reached with the three unit axes as hints
  return x.normalized();
}

P frame_from(const Vector3d& origin, const Vector3d& x, const Vector3d& z) {
  P F;
  F.R.col(0) = x;
  F.R.col(1) = z.cross(x);
  F.R.col(2) = z;
  F.p = origin;
  return F;
}

// The DH row that carries frame B (z on the joint axis) to frame D: D = B Rz(theta) Tz(d) Tx(a) Rx(alpha).
// D's x axis must be perpendicular to B's z axis and meet it; the construction guarantees it.
DHParameters<double> dh_row(const P& B, const P& D, const std::string& who) {
  const P T = B.inverse() * D;
  const Vector3d x = T.R.col(0), z = T.R.col(2);
  DHParameters<double> dh;
  dh.theta = std::atan2(x.y(), x.x());
  const double c = std::cos(dh.theta), s = std::sin(dh.theta);
  dh.d = T.p.z();
  dh.a = T.p.x() * c + T.p.y() * s;
  const Vector3d zr(c * z.x() + s * z.y(), -s * z.x() + c * z.y(), z.z());  // Rz(-theta) z = (0, -sin a, cos a)
  dh.alpha = std::atan2(-zr.y(), zr.z());
  // the row must rebuild the frame; anything else is a bug in the frame construction
  P check = rotation_about(Vector3d::UnitZ(), dh.theta);
  check.p = Vector3d(dh.a * c, dh.a * s, dh.d);
  check.R = check.R * Eigen::AngleAxisd(dh.alpha, Vector3d::UnitX()).toRotationMatrix();
  if ((check.R - T.R).cwiseAbs().maxCoeff() > 1e-9 || (check.p - T.p).cwiseAbs().maxCoeff() > 1e-9)
    fail(who + ": internal error: the DH frame is not reachable by a DH row");
  return dh;
}

// The DH frame of a link whose joint turns about `own` and whose next joint turns about `next`
// (both in the body's reference frame, whose x axis breaks ties); nothing when the common normal
// lies too far away (kFar).
std::optional<P> dh_frame(const Line& own, const Line& next) {
  const Vector3d z = next.u;
  const Vector3d cross = own.u.cross(next.u);
  if (cross.norm() > kParallel) {
    // the closest points o + s u of the two lines, from cross products with n = u_own x u_next:
    // s = (w x u_next) . n / |n|^2, t = (w x u_own) . n / |n|^2 (with 1 - (u_own . u_next)^2 as the
    // denominator, it rounds to 0 for axes 1e-8 rad apart, and loses the lines' digits long before)
    const Vector3d w = next.o - own.o, n = cross.normalized();
    const double s = w.cross(next.u).dot(cross) / cross.squaredNorm();
    const double t = w.cross(own.u).dot(cross) / cross.squaredNorm();
    if (!(std::abs(s) <= kFar && std::abs(t) <= kFar)) return std::nullopt;
    const Vector3d p_next = next.o + t * next.u;
    const double distance = w.dot(n);  // along n, from the own axis to the next one
    if (std::abs(distance) > kMeet) return frame_from(p_next, distance > 0 ? n : Vector3d(-n), z);  // skew
    // intersecting: x along own x next, turned to agree with the body's x axis
    Vector3d x = cross.normalized();
    if (x.x() < -1e-12 || (std::abs(x.x()) <= 1e-12 && (x.y() < -1e-12 || (std::abs(x.y()) <= 1e-12 && x.z() < 0))))
      x = -x;
    return frame_from(p_next, x, z);
  }
  // parallel or anti-parallel: the common normal through the next joint's origin
  const Vector3d w = (next.o - own.o) - (next.o - own.o).dot(own.u) * own.u;
  if (w.norm() > kMeet) return frame_from(next.o, w.normalized(), z);
  // coincident: x from the body's x axis
  return frame_from(next.o, perpendicular(z, {Vector3d::UnitX(), Vector3d::UnitY(), Vector3d::UnitZ()}), z);
}

// The frame of a joint turning about `axis` that hangs from frame F off F's z axis: on the axis at
// the point nearest F's origin, x from F's x axis.
P mount_frame(const P& F, const Line& axis) {
  const Vector3d o = axis.o + (F.p - axis.o).dot(axis.u) * axis.u;
  return frame_from(o, perpendicular(axis.u, {F.R.col(0), F.R.col(1), F.R.col(2)}), axis.u);
}

bool on_z_axis(const P& F, const Line& axis) {
  if ((axis.u - F.R.col(2)).norm() > kParallel) return false;
  const Vector3d r = axis.o - F.p;
  return (r - r.dot(axis.u) * axis.u).norm() <= kMeet;
}

bool is_identity(const P& X) {
  return (X.R - Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-12 && X.p.cwiseAbs().maxCoeff() <= 1e-12;
}

// Adds a body, given in a frame that X places in the lumped body's frame, to a lumped inertia.
void lump(RigidBodyInertia<double>& sum, const RigidBodyInertia<double>& b, const P& X) {
  if (b.mass == 0 && b.inertia.isZero()) return;
  sum += b.expressed_in(X);
}

}  // namespace

Import import_urdf(const std::string& xml, const ImportOptions& options, const std::string& source) {
  std::vector<std::string> warnings;
  const UrdfDocument doc = detail::read_urdf_document(xml, source, options.balance_inertia, warnings);
  const int nl = int(doc.links.size()), nu = int(doc.joints.size());

  // which joints move: the joint map's active entries, or every revolute and continuous joint
  std::vector<bool> active(std::size_t(nu), false);
  std::vector<double> locked_value(std::size_t(nu), 0.0);
  std::vector<std::string> model_name(static_cast<std::size_t>(nu));
  std::vector<int> rank(static_cast<std::size_t>(nu));  // order of chains at a branch point
  for (int j = 0; j < nu; ++j) {
    model_name[std::size_t(j)] = doc.joints[std::size_t(j)].name;
    rank[std::size_t(j)] = j;
  }
  if (options.joints) {
    const JointMap& map = *options.joints;
    std::vector<bool> seen(std::size_t(nu), false);
    std::map<std::string, std::size_t> named;  // model name -> its entry
    for (std::size_t e = 0; e < map.entries.size(); ++e) {
      const auto& entry = map.entries[e];
      const std::string where =
          map.source + ":" + std::to_string(entry.line) + ": joint '" + text::shown(entry.urdf_joint) + "'";
      const int j = doc.find_joint(entry.urdf_joint);
      if (j < 0) fail(where + ": no such joint in " + source);
      if (seen[std::size_t(j)]) fail(where + ": listed twice");
      seen[std::size_t(j)] = true;
      const auto& uj = doc.joints[std::size_t(j)];
      if (entry.locked) {
        if ((uj.type == JointType::Floating || uj.type == JointType::Planar || uj.type == JointType::Fixed) &&
            entry.value != 0)
          fail(where + ": a " + std::string(detail::type_name(uj.type)) + " joint can only be locked at 0");
        locked_value[std::size_t(j)] = entry.value;
      } else {
        if (uj.type == JointType::Fixed) fail(where + ": a fixed joint cannot become a model joint");
        active[std::size_t(j)] = true;
        model_name[std::size_t(j)] = entry.model_name.empty() ? uj.name : entry.model_name;
        rank[std::size_t(j)] = int(e) - int(map.entries.size());  // listed joints first, in list order
        // a model joint's name heads CSV columns (URDF names are checked as the file is read)
        if (const std::string fault = name_fault(model_name[std::size_t(j)]); !fault.empty())
          fail(where + ": model name '" + text::shown(model_name[std::size_t(j)]) + "': " + fault +
               ", so no CSV column can name it");
        // two columns with one name could not be told apart
        if (const auto [it, added] = named.emplace(model_name[std::size_t(j)], e); !added) {
          const auto& first = map.entries[it->second];
          fail(where + ": model name '" + text::shown(model_name[std::size_t(j)]) + "' is already given to joint '" +
               text::shown(first.urdf_joint) + "' (line " + std::to_string(first.line) + ")");
        }
      }
    }
  } else {
    for (int j = 0; j < nu; ++j) active[std::size_t(j)] = doc.joints[std::size_t(j)].type != JointType::Fixed;
  }
  // a model has at least one joint (the model JSON reader refuses none)
  if (std::find(active.begin(), active.end(), true) == active.end()) {
    if (options.joints)
      fail(options.joints->source +
           ": the joint map leaves no model joint: it lists none without '= value', so every joint of " + source +
           " is locked");
    fail(source + ": no revolute or continuous joint: a model needs at least one joint");
  }
  for (int j = 0; j < nu; ++j) {
    if (!active[std::size_t(j)]) continue;
    const auto& uj = doc.joints[std::size_t(j)];
    const std::string why = options.joints ? "" : "; a joint map can lock it";
    if (uj.type == JointType::Prismatic || uj.type == JointType::Floating || uj.type == JointType::Planar)
      fail(doc.where_joint(j) + ": " + detail::type_name(uj.type) +
           " joints are not supported: every model joint is revolute" + why);
    if (uj.mimic) fail(doc.where_joint(j) + ": mimic joints are not supported: a model joint moves on its own" + why);
  }

  // the transform of a locked or fixed joint: child frame in parent frame
  const auto rigid = [&](int j) {
    const auto& uj = doc.joints[std::size_t(j)];
    const double v = locked_value[std::size_t(j)];
    switch (uj.type) {
      case JointType::Revolute:
      case JointType::Continuous:
        return uj.origin * rotation_about(uj.axis, v);
      case JointType::Prismatic:
        return uj.origin * P{Matrix3d::Identity(), v * uj.axis};
      default:
        return uj.origin;
    }
  };

  // the base link
  int root = doc.root;
  if (!options.root.empty()) {
    root = doc.find_link(options.root);
    if (root < 0) {
      std::string links;  // the first twenty, to choose from
      for (std::size_t l = 0; l < doc.links.size() && l < 20; ++l)
        links += (l == 0 ? "" : ", ") + text::shown(doc.links[l].name);
      fail(source + ": no link '" + text::shown(options.root) + "' to use as the base; the links: " + links +
           (doc.links.size() > 20 ? ", ... (" + std::to_string(doc.links.size()) + " in all)" : ""));
    }
  }
  // stableNorm: components near 1e155 would overflow a plain sum of squares
  const double g_norm = options.gravity.stableNorm();
  if (!options.gravity.allFinite() || !std::isfinite(g_norm))
    fail("gravity is not finite: its magnitude overflows a double (above 1.8e308 m/s^2)");

  // 1-2. walk the links from the base: bodies, their anchor frames, and the tree of model joints
  struct Body {
    int anchor = -1;
    int joint = -1;  // the URDF joint that moves it (-1: base)
    bool reversed = false;
    int parent = -1;  // parent body
    Line axis;        // the joint's axis in the parent body's frame
    P X0;             // this body's frame in the parent body's frame at q = 0
    std::vector<int> links;
    std::vector<int> children;  // child bodies
  };
  std::vector<Body> bodies;
  std::vector<int> body_of(std::size_t(nl), -1);
  std::vector<P> in_body(static_cast<std::size_t>(nl));  // link frame in its body's frame
  std::vector<int> stack;                                // links to expand
  const auto enter = [&](int link, int body, const P& X) {
    body_of[std::size_t(link)] = body;
    in_body[std::size_t(link)] = X;
    bodies[std::size_t(body)].links.push_back(link);
    stack.push_back(link);
  };
  bodies.push_back(Body{root, -1, false, -1, {}, P{}, {}, {}});
  enter(root, 0, P{});
  // A link's neighbours: its child joints and its parent joint. Rigid ones extend the body now;
  // model joints start new bodies, expanded after the current body is complete.
  std::vector<std::pair<int, int>> pending;  // (joint, from link)
  std::size_t next_pending = 0;
  for (;;) {
    while (!stack.empty()) {
      const int l = stack.back();
      stack.pop_back();
      const auto& link = doc.links[std::size_t(l)];
      std::vector<int> around = link.child_joints;
      if (link.parent_joint >= 0) around.push_back(link.parent_joint);
      for (const int j : around) {
        const auto& uj = doc.joints[std::size_t(j)];
        const int other = uj.parent == l ? uj.child : uj.parent;
        if (body_of[std::size_t(other)] >= 0) continue;
        if (active[std::size_t(j)]) {
          pending.emplace_back(j, l);
          continue;
        }
        const P X = uj.parent == l ? rigid(j) : rigid(j).inverse();
        enter(other, body_of[std::size_t(l)], in_body[std::size_t(l)] * X);
      }
    }
    if (next_pending == pending.size()) break;
    const auto [j, from] = pending[next_pending++];
    const auto& uj = doc.joints[std::size_t(j)];
    const bool reversed = uj.child == from;
    const int other = reversed ? uj.parent : uj.child;
    if (body_of[std::size_t(other)] >= 0) continue;
    const int parent_body = body_of[std::size_t(from)];
    const P& Xf = in_body[std::size_t(from)];
    Body b;
    b.anchor = other;
    b.joint = j;
    b.reversed = reversed;
    b.parent = parent_body;
    if (!reversed) {
      // X_PC(q) = origin * Rot(axis, q): the axis through the joint frame's origin
      const P J = Xf * uj.origin;
      b.axis = {J.p, J.R * uj.axis};
      b.X0 = J;
    } else {
      // X_CP(q) = Rot(-axis, q) * origin^-1: the same line, turned the other way
      b.axis = {Xf.p, -(Xf.R * uj.axis)};
      b.X0 = Xf * uj.origin.inverse();
    }
    const int id = int(bodies.size());
    bodies.push_back(b);
    bodies[std::size_t(parent_body)].children.push_back(id);
    enter(other, id, P{});
  }

  // model joint order: depth first from the base, children by joint map order or document order
  for (auto& b : bodies)
    std::sort(b.children.begin(), b.children.end(), [&](int x, int y) {
      return rank[std::size_t(bodies[std::size_t(x)].joint)] < rank[std::size_t(bodies[std::size_t(y)].joint)];
    });
  std::vector<int> order;  // body ids in model joint order
  std::vector<int> index_of(bodies.size(), -1);
  {
    std::vector<int> todo(bodies[0].children.rbegin(), bodies[0].children.rend());
    while (!todo.empty()) {
      const int b = todo.back();
      todo.pop_back();
      index_of[std::size_t(b)] = int(order.size());
      order.push_back(b);
      const auto& ch = bodies[std::size_t(b)].children;
      todo.insert(todo.end(), ch.rbegin(), ch.rend());
    }
  }

  // 3. DH frames, in each body's own frame. The base frame is the base link's frame.
  std::vector<P> D(bodies.size());
  const auto axis_in_own_frame = [&](int b) {
    const auto& body = bodies[std::size_t(b)];
    return transform(body.X0.inverse(), body.axis);
  };
  for (std::size_t b = 1; b < bodies.size(); ++b) {
    const auto& body = bodies[b];
    const Line own = axis_in_own_frame(int(b));
    if (!body.children.empty()) {
      if (const auto frame = dh_frame(own, bodies[std::size_t(body.children.front())].axis)) {
        D[b] = *frame;
        continue;
      }
    }
    // the last link of a chain (or one whose next axis is nearly parallel, far off): a tip frame fixed
    // to it, when a DH row reaches it, else on its own axis; its children then hang from mounts
    bool found = false;
    for (const int l : body.links) {
      if (l == body.anchor || !doc.links[std::size_t(l)].child_joints.empty()) continue;
      const P& T = in_body[std::size_t(l)];
      const Vector3d x = T.R.col(0);
      if (std::abs(x.dot(own.u)) > kParallel) continue;
      // the x axis line must meet the joint axis
      const Vector3d r = T.p - own.o;
      const Vector3d n = own.u.cross(x);
      if (std::abs(r.dot(n)) > kMeet) continue;
      D[b] = T;
      found = true;
      break;
    }
    if (!found) {
      const Vector3d o = own.o + (Vector3d::Zero() - own.o).dot(own.u) * own.u;
      D[b] = frame_from(o, perpendicular(own.u, {Vector3d::UnitX(), Vector3d::UnitY(), Vector3d::UnitZ()}), own.u);
    }
  }

  // 4. the description: mounts, DH rows, lumped inertias, link placements
  Import out;
  out.warnings = std::move(warnings);
  auto& m = out.model;
  m.name = doc.name;
  m.base_link_name = doc.links[std::size_t(root)].name;
  for (const int l : bodies[0].links) lump(m.base_body, doc.links[std::size_t(l)].body, in_body[std::size_t(l)]);
  {
    // the world: the base link's frame turned so that gravity points down z
    const double g = g_norm;
    if (g > 0) {
      const Vector3d up = -options.gravity / g;
      const Vector3d x = perpendicular(up, {Vector3d::UnitX(), Vector3d::UnitY()});
      m.base_pose.R.row(0) = x.transpose();
      m.base_pose.R.row(1) = up.cross(x).transpose();
      m.base_pose.R.row(2) = up.transpose();
    }
    m.gravity = Vector3d(0, 0, -g);
  }
  for (const int b : order) {
    const auto& body = bodies[std::size_t(b)];
    const int parent = body.parent;
    const P Dp = parent == 0 ? P{} : D[std::size_t(parent)];
    JointDescription<double> jd;
    jd.name = model_name[std::size_t(body.joint)];
    jd.link_name = doc.links[std::size_t(body.anchor)].name;
    jd.parent = parent == 0 ? -1 : index_of[std::size_t(parent)];
    // the joint's frame on its axis: the parent's DH frame when the axis is its z axis, else a mount
    P B = Dp;
    if (!on_z_axis(Dp, body.axis)) {
      B = mount_frame(Dp, body.axis);
      const P mount = Dp.inverse() * B;
      if (!is_identity(mount)) {
        jd.mounted = true;
        jd.mount = mount;
      }
    }
    jd.dh = dh_row(B, body.X0 * D[std::size_t(b)], doc.where_joint(body.joint));
    const P Dinv = D[std::size_t(b)].inverse();
    for (const int l : body.links) lump(jd.body, doc.links[std::size_t(l)].body, Dinv * in_body[std::size_t(l)]);
    m.joints.push_back(jd);
    out.urdf_joints.push_back(doc.joints[std::size_t(body.joint)].name);
    out.reversed.push_back(body.reversed);
  }
  for (int l = 0; l < nl; ++l) {
    const int b = body_of[std::size_t(l)];
    LinkPlacement p;
    p.link = doc.links[std::size_t(l)].name;
    if (b == 0) {
      p.pose = in_body[std::size_t(l)];
    } else {
      p.joint = index_of[std::size_t(b)];
      p.pose = D[std::size_t(b)].inverse() * in_body[std::size_t(l)];
    }
    out.links.push_back(p);
  }
  // what the importer gives is a valid model
  try {
    const AnyModel<double> check(m);
  } catch (const ModelError& e) {
    fail(source + ": the imported model is invalid: " + e.what());
  }
  return out;
}

Import import_urdf_file(const std::string& path, const ImportOptions& options) {
  std::string content;
  if (const std::string fault = text::read_whole_file(path, content); !fault.empty())
    fail(text::shown(path) + ": " + fault);
  return import_urdf(content, options, text::shown(path));
}

Eigen::Vector3d gravity_for_up(const std::string& axis, double g) {
  static const std::map<std::string, Vector3d> axes{{"x", Vector3d::UnitX()},   {"y", Vector3d::UnitY()},
                                                    {"z", Vector3d::UnitZ()},   {"-x", -Vector3d::UnitX()},
                                                    {"-y", -Vector3d::UnitY()}, {"-z", -Vector3d::UnitZ()}};
  const auto it = axes.find(axis);
  if (it == axes.end())
    throw std::invalid_argument("unknown up axis '" + text::shown(axis) + "' (expected x, y, z, -x, -y or -z)");
  return -g * it->second;
}

}  // namespace humandyn::urdf
