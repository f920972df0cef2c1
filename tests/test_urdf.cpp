// The URDF importer against the URDF's own kinematics (urdfdom poses composed link by link), KDL's
// inverse dynamics on the same file (kdl_parser's tree, or a KDL tree re-rooted here by hand) and the
// inertials read from the XML by the test itself, on third-party files, small URDFs for every relation
// of consecutive axes, a round trip through the exporter, a physics identity on a re-rooted reduced
// human, the failing inputs of ../shared/cases, and bad input.
#include "fuzz/fuzz_inputs.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/urdf.hpp"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>
#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <kdl_parser/kdl_parser.hpp>

#include <Eigen/Geometry>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

namespace test_urdf {

namespace {

using namespace humandyn;
namespace hu = humandyn::urdf;
using Eigen::Vector3d;
using P = Pose<double>;
using Q = std::map<std::string, double>;  // URDF joint angles by name

std::string shared_urdf(const std::string& name) { return std::string(HUMANDYN_SHARED_DATA) + "/urdf/" + name; }

#define REQUIRE_FILE(path)                                                                           \
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data file " << (path) << " is absent"; \
  static_assert(true)

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

::urdf::ModelInterfaceSharedPtr parse(const std::string& xml) {
  auto m = ::urdf::parseURDF(xml);
  if (!m) throw std::runtime_error("urdfdom rejects the test's URDF");
  return m;
}

P to_pose(const ::urdf::Pose& p) {
  P X;
  X.R = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).toRotationMatrix();
  X.p = Vector3d(p.position.x, p.position.y, p.position.z);
  return X;
}

// The transform a URDF joint makes at angle q: child frame in parent frame.
P joint_transform(const ::urdf::Joint& j, double q) {
  P X = to_pose(j.parent_to_joint_origin_transform);
  if (j.type == ::urdf::Joint::REVOLUTE || j.type == ::urdf::Joint::CONTINUOUS) {
    P R;
    R.R = Eigen::AngleAxisd(q, Vector3d(j.axis.x, j.axis.y, j.axis.z).normalized()).toRotationMatrix();
    X = X * R;
  }
  return X;
}

// Every link's frame in the URDF root frame, composed from urdfdom's joints.
std::map<std::string, P> urdf_poses(const ::urdf::ModelInterface& m, const Q& q) {
  std::map<std::string, P> out;
  std::vector<::urdf::LinkConstSharedPtr> todo{m.getRoot()};
  out[m.getRoot()->name] = P{};
  while (!todo.empty()) {
    const auto l = todo.back();
    todo.pop_back();
    for (const auto& j : l->child_joints) {
      const auto it = q.find(j->name);
      out[j->child_link_name] = out[l->name] * joint_transform(*j, it == q.end() ? 0.0 : it->second);
      todo.push_back(m.getLink(j->child_link_name));
    }
  }
  return out;
}

KDL::Frame kdl(const P& X) {
  return KDL::Frame(
      KDL::Rotation(X.R(0, 0), X.R(0, 1), X.R(0, 2), X.R(1, 0), X.R(1, 1), X.R(1, 2), X.R(2, 0), X.R(2, 1), X.R(2, 2)),
      KDL::Vector(X.p.x(), X.p.y(), X.p.z()));
}

KDL::RigidBodyInertia kdl_inertia(const ::urdf::Link& l) {
  if (!l.inertial) return KDL::RigidBodyInertia();
  const auto& in = *l.inertial;
  const P X = to_pose(in.origin);
  const KDL::RigidBodyInertia local(in.mass, KDL::Vector::Zero(),
                                    KDL::RotationalInertia(in.ixx, in.iyy, in.izz, in.ixy, in.ixz, in.iyz));
  return kdl(X) * local;
}

// The URDF as a KDL tree rooted at any link, built here independently of the importer: a joint walked
// from child to parent becomes a segment turning about the negated axis, X_CP(q) = Rot(-axis, q) origin^-1.
// Joints listed in `locked` are fixed at that angle.
KDL::Tree kdl_tree_at(const ::urdf::ModelInterface& m, const std::string& root, const Q& locked = {}) {
  KDL::Tree tree(root);
  std::vector<std::string> todo{root};
  std::set<std::string> done{root};
  while (!todo.empty()) {
    const std::string l = todo.back();
    todo.pop_back();
    const auto link = m.getLink(l);
    std::vector<::urdf::JointSharedPtr> around(link->child_joints.begin(), link->child_joints.end());
    if (link->parent_joint) around.push_back(link->parent_joint);
    for (const auto& j : around) {
      const bool forward = j->parent_link_name == l;
      const std::string other = forward ? j->child_link_name : j->parent_link_name;
      if (done.count(other)) continue;
      done.insert(other);
      const auto lk = locked.find(j->name);
      const bool moves =
          (j->type == ::urdf::Joint::REVOLUTE || j->type == ::urdf::Joint::CONTINUOUS) && lk == locked.end();
      const P O = joint_transform(*j, lk == locked.end() ? 0.0 : lk->second);
      const Vector3d axis = Vector3d(j->axis.x, j->axis.y, j->axis.z).normalized();
      KDL::Joint joint(j->name + "_fixed", KDL::Joint::Fixed);
      P tip;
      if (forward) {
        tip = O;
        if (moves)
          joint =
              KDL::Joint(j->name, kdl(O).p, kdl(O).M * KDL::Vector(axis.x(), axis.y(), axis.z()), KDL::Joint::RotAxis);
      } else {
        tip = O.inverse();
        if (moves)
          joint = KDL::Joint(j->name, KDL::Vector::Zero(), KDL::Vector(-axis.x(), -axis.y(), -axis.z()),
                             KDL::Joint::RotAxis);
      }
      if (!tree.addSegment(KDL::Segment(other, joint, kdl(tip), kdl_inertia(*m.getLink(other))), l))
        throw std::runtime_error("KDL refused " + other);
      todo.push_back(other);
    }
  }
  return tree;
}

// KDL's joint names in its q order.
std::vector<std::string> kdl_joint_names(const KDL::Tree& tree) {
  std::vector<std::string> names(tree.getNrOfJoints());
  for (const auto& [name, el] : tree.getSegments()) {
    const auto& seg = GetTreeElementSegment(el);
    if (seg.getJoint().getType() != KDL::Joint::None) names[GetTreeElementQNr(el)] = seg.getJoint().getName();
  }
  return names;
}

struct State {
  Eigen::VectorXd q, qd, qdd;
};

State random_state(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  State s{Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n)};
  for (int i = 0; i < n; ++i) {
    s.q[i] = 1.0 * u(rng);
    s.qd[i] = 2.0 * u(rng);
    s.qdd[i] = 5.0 * u(rng);
  }
  return s;
}

// Forward kinematics of every URDF link: the imported model against urdfdom's composition, relative
// to the base link, on `trials` random configurations. Returns the largest position error (m).
double fk_error(const hu::Import& imp, const std::string& xml, const Q& locked, int trials, double* rot_err) {
  const auto m = parse(xml);
  const AnyModel<double> model(imp.model);
  Data<AnyModel<double>> data(model);
  std::mt19937 rng(7);
  double err = 0, rerr = 0;
  for (int t = 0; t < trials; ++t) {
    const State s = random_state(model.size(), rng);
    Q q = locked;
    for (int i = 0; i < model.size(); ++i) q[imp.urdf_joints[std::size_t(i)]] = s.q[i];
    forward_kinematics(model, data, s.q);
    const auto ref = urdf_poses(*m, q);
    const P ref_base_inv = ref.at(imp.model.base_link_name).inverse();
    const P base_inv = imp.model.base_pose.inverse();
    for (const auto& pl : imp.links) {
      const P world = (pl.joint < 0 ? imp.model.base_pose : data.oMi[std::size_t(pl.joint)]) * pl.pose;
      const P mine = base_inv * world, theirs = ref_base_inv * ref.at(pl.link);
      err = std::max(err, (mine.p - theirs.p).cwiseAbs().maxCoeff());
      rerr = std::max(rerr, (mine.R - theirs.R).cwiseAbs().maxCoeff());
    }
  }
  if (rot_err) *rot_err = rerr;
  return err;
}

// Inverse dynamics of the imported model against KDL's TreeIdSolver_RNE on `tree` (same joints by
// name; joints the model lacks held at `locked`, still). Returns the largest torque error (N m).
double id_error(const hu::Import& imp, const KDL::Tree& tree, const Q& locked, int trials, double* scale = nullptr) {
  const AnyModel<double> model(imp.model);
  Data<AnyModel<double>> data(model);
  const Vector3d g = imp.model.base_pose.R.transpose() * imp.model.gravity;
  KDL::TreeIdSolver_RNE solver(tree, KDL::Vector(g.x(), g.y(), g.z()));
  const auto names = kdl_joint_names(tree);
  const unsigned nk = tree.getNrOfJoints();
  KDL::JntArray q(nk), qd(nk), qdd(nk), tau(nk);
  std::map<std::string, int> model_index;
  for (int i = 0; i < model.size(); ++i) model_index[imp.urdf_joints[std::size_t(i)]] = i;
  std::mt19937 rng(11);
  double err = 0, big = 0;
  for (int t = 0; t < trials; ++t) {
    const State s = random_state(model.size(), rng);
    for (unsigned k = 0; k < nk; ++k) {
      const auto it = model_index.find(names[k]);
      const auto lk = locked.find(names[k]);
      q(k) = it != model_index.end() ? s.q[it->second] : (lk == locked.end() ? 0.0 : lk->second);
      qd(k) = it != model_index.end() ? s.qd[it->second] : 0.0;
      qdd(k) = it != model_index.end() ? s.qdd[it->second] : 0.0;
    }
    if (solver.CartToJnt(q, qd, qdd, KDL::WrenchMap(), tau) < 0) throw std::runtime_error("KDL solver failed");
    rnea<Terms::Full>(model, data, s.q, s.qd, s.qdd);
    for (unsigned k = 0; k < nk; ++k) {
      const auto it = model_index.find(names[k]);
      if (it == model_index.end()) continue;
      err = std::max(err, std::abs(data.tau[it->second] - tau(k)));
      big = std::max(big, std::abs(tau(k)));
    }
  }
  if (scale) *scale = big;
  return err;
}

// The kdl_parser tree of a URDF string (parsed with urdfdom first, checked).
KDL::Tree kdl_parser_tree(const std::string& xml) {
  const auto m = parse(xml);
  KDL::Tree tree;
  if (!kdl_parser::treeFromUrdfModel(*m, tree)) throw std::runtime_error("kdl_parser failed");
  return tree;
}

// ---------------------------------------------------------------------------------------------------
// The inertials as the XML writes them, read here with tinyxml2 (not urdfdom), and the model's bodies
// summed from them: what every import must carry, whatever the parser did.

// R = Rz(yaw) Ry(pitch) Rx(roll), URDF's rpy
Eigen::Matrix3d rpy_matrix(const Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Vector3d::UnitX()))
      .toRotationMatrix();
}

Vector3d attr3(const tinyxml2::XMLElement* e, const char* name) {
  Vector3d v = Vector3d::Zero();
  if (const char* t = e ? e->Attribute(name) : nullptr) std::istringstream(t) >> v.x() >> v.y() >> v.z();
  return v;
}

double attr1(const tinyxml2::XMLElement* e, const char* name) {
  const char* t = e ? e->Attribute(name) : nullptr;
  if (!t) throw std::runtime_error(std::string("the test's XML read: no attribute ") + name);
  return std::stod(t);
}

// Per link: mass, centre of mass and inertia about it, in the link's frame (massless: zeros).
std::map<std::string, RigidBodyInertia<double>> xml_inertials(const std::string& xml) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS)
    throw std::runtime_error("the test's XML read failed");
  std::map<std::string, RigidBodyInertia<double>> out;
  for (const auto* l = doc.RootElement()->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
    RigidBodyInertia<double> b;
    if (const auto* in = l->FirstChildElement("inertial")) {
      const auto* o = in->FirstChildElement("origin");
      const Eigen::Matrix3d R = rpy_matrix(attr3(o, "rpy"));
      const auto* I = in->FirstChildElement("inertia");
      Eigen::Matrix3d J;
      J << attr1(I, "ixx"), attr1(I, "ixy"), attr1(I, "ixz"), attr1(I, "ixy"), attr1(I, "iyy"), attr1(I, "iyz"),
          attr1(I, "ixz"), attr1(I, "iyz"), attr1(I, "izz");
      b.mass = attr1(in->FirstChildElement("mass"), "value");
      b.com = attr3(o, "xyz");
      b.inertia = R * J * R.transpose();
    }
    out[l->Attribute("name")] = b;
  }
  return out;
}

// Every model link's body (and the base body) equals the sum of the XML inertials of the URDF links
// the import placed on it (Import::links), by the parallel-axis theorem, and the total mass is the XML's.
void expect_inertials_match_xml(const hu::Import& imp, const std::string& xml) {
  const auto authored = xml_inertials(xml);
  const int n = int(imp.model.joints.size());
  std::vector<double> mass(std::size_t(n + 1), 0.0);
  std::vector<Vector3d> first(std::size_t(n + 1), Vector3d::Zero());                 // sum of m c
  std::vector<Eigen::Matrix3d> second(std::size_t(n + 1), Eigen::Matrix3d::Zero());  // sum of I_c + m (|c|^2 1 - c c^T)
  double total = 0, scale = 0;
  for (const auto& pl : imp.links) {
    const auto& b = authored.at(pl.link);
    const std::size_t k = std::size_t(pl.joint + 1);
    const Vector3d c = pl.pose * b.com;
    mass[k] += b.mass;
    first[k] += b.mass * c;
    second[k] += pl.pose.R * b.inertia * pl.pose.R.transpose() +
                 b.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    total += b.mass;
    scale = std::max(scale, b.inertia.cwiseAbs().maxCoeff());
  }
  double model_total = imp.model.base_body.mass;
  for (int k = 0; k <= n; ++k) {
    const auto& body = k == 0 ? imp.model.base_body : imp.model.joints[std::size_t(k - 1)].body;
    SCOPED_TRACE(k == 0 ? "base body" : "model link " + imp.model.joints[std::size_t(k - 1)].link_name);
    if (k > 0) model_total += body.mass;
    const double m = mass[std::size_t(k)];
    EXPECT_NEAR(body.mass, m, 1e-12 * std::max(1.0, m));
    // the body's own sums about the link frame's origin, from its centre of mass and inertia
    const Vector3d mc = body.mass * body.com;
    const Eigen::Matrix3d about_origin =
        body.inertia +
        body.mass * (body.com.squaredNorm() * Eigen::Matrix3d::Identity() - body.com * body.com.transpose());
    const double tol = 1e-12 * std::max({1.0, m, scale});
    EXPECT_LE((mc - first[std::size_t(k)]).cwiseAbs().maxCoeff(), tol);
    EXPECT_LE((about_origin - second[std::size_t(k)]).cwiseAbs().maxCoeff(), tol);
  }
  EXPECT_NEAR(model_total, total, 1e-12 * std::max(1.0, total));
}

// Imports a third-party file, checks FK on 100 configurations and inverse dynamics on 1000 states
// against kdl_parser's tree (at the URDF root) or a hand-rooted KDL tree (elsewhere).
void check_file(const std::string& file, const std::string& root, const std::string& up) {
  const std::string xml = read_text(file);
  hu::ImportOptions opt;
  opt.root = root;
  opt.gravity = hu::gravity_for_up(up);
  const auto imp = hu::import_urdf(xml, opt, file);
  expect_inertials_match_xml(imp, xml);
  double rot = 0;
  const double fk = fk_error(imp, xml, {}, 100, &rot);
  EXPECT_LE(fk, 1e-12) << file << " at " << root;
  EXPECT_LE(rot, 1e-12) << file << " at " << root;
  const auto m = parse(xml);
  const KDL::Tree tree = root.empty() ? kdl_parser_tree(xml) : kdl_tree_at(*m, root);
  double scale = 0;
  const double err = id_error(imp, tree, {}, 1000, &scale);
  EXPECT_LE(err, 1e-9) << file << " at " << root << " (largest torque " << scale << " N m)";
  EXPECT_GT(scale, 1.0) << "the comparison must see real torques";
  std::printf(
      "[ measured ] %s rooted at %s: %zu joints; FK %.1e m, %.1e rotation; torques %.1e N m off KDL's (largest %.0f N "
      "m)\n",
      std::filesystem::path(file).filename().c_str(), root.empty() ? "its root" : root.c_str(), imp.model.joints.size(),
      fk, rot, err, scale);
}

TEST(UrdfThirdParty, Human36MatchesUrdfdomAndKdl) {
  REQUIRE_FILE(shared_urdf("human36_isb.urdf"));
  check_file(shared_urdf("human36_isb.urdf"), "", "y");
  check_file(shared_urdf("human36_isb.urdf"), "right_foot", "y");
  check_file(shared_urdf("human36_isb.urdf"), "left_hand", "y");
  const auto imp = hu::import_urdf_file(shared_urdf("human36_isb.urdf"));
  EXPECT_EQ(imp.model.joints.size(), 36u);
}

TEST(UrdfThirdParty, SimpleHumanoidMatchesUrdfdomAndKdl) {
  REQUIRE_FILE(shared_urdf("simple_humanoid.urdf"));
  check_file(shared_urdf("simple_humanoid.urdf"), "", "z");
  check_file(shared_urdf("simple_humanoid.urdf"), "r_ankle", "z");  // re-rooted at the right foot
}

TEST(UrdfThirdParty, Ur5MatchesUrdfdomAndKdl) {
  REQUIRE_FILE(shared_urdf("ur5_robot.urdf"));
  check_file(shared_urdf("ur5_robot.urdf"), "", "z");
  check_file(shared_urdf("ur5_robot.urdf"), "ee_link", "z");
}

// ---------------------------------------------------------------------------------------------------
// Small URDFs: every relation of consecutive joint axes

struct JointSpec {
  std::string xyz, rpy, axis;
  std::string parent;  // parent link name (default: the previous link)
};

// A tree of links l0 (root), l1, ... each with a mass off its origin; joint k moves link k+1.
std::string tree_urdf(const std::vector<JointSpec>& joints) {
  std::ostringstream x;
  x << "<robot name=\"t\">\n";
  for (std::size_t k = 0; k <= joints.size(); ++k)
    x << "<link name=\"l" << k << "\"><inertial><origin xyz=\"0.05 " << 0.01 * double(k) << " 0.1\" rpy=\"0.1 0.2 "
      << 0.3 * double(k) << "\"/><mass value=\"" << 1.0 + double(k)
      << "\"/><inertia ixx=\"0.03\" ixy=\"0.001\" ixz=\"0\""
      << " iyy=\"0.02\" iyz=\"0.002\" izz=\"0.025\"/></inertial></link>\n";
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const auto& j = joints[k];
    x << "<joint name=\"j" << k + 1 << "\" type=\"continuous\"><parent link=\""
      << (j.parent.empty() ? "l" + std::to_string(k) : j.parent) << "\"/><child link=\"l" << k + 1 << "\"/>"
      << "<origin xyz=\"" << j.xyz << "\" rpy=\"" << j.rpy << "\"/><axis xyz=\"" << j.axis << "\"/></joint>\n";
  }
  x << "</robot>\n";
  return x.str();
}

// Imports `xml` at `root`, checks FK against urdfdom and inverse dynamics against KDL; returns the import.
hu::Import check_small(const std::string& xml, const std::string& root = "") {
  hu::ImportOptions opt;
  opt.root = root;
  opt.gravity = Vector3d(0.3, -1.2, -9.7);
  const auto imp = hu::import_urdf(xml, opt, "small.urdf");
  expect_inertials_match_xml(imp, xml);
  double rot = 0;
  EXPECT_LE(fk_error(imp, xml, {}, 100, &rot), 1e-12);
  EXPECT_LE(rot, 1e-12);
  const auto m = parse(xml);
  const KDL::Tree tree = root.empty() ? kdl_parser_tree(xml) : kdl_tree_at(*m, root);
  double scale = 0;
  EXPECT_LE(id_error(imp, tree, {}, 300, &scale), 1e-9);
  EXPECT_GT(scale, 0.1);
  return imp;
}

constexpr double kPi = 3.14159265358979323846;

// joint 1 turns about l1's z (tilted from the base, so it has a mount whose origin is l1's); joint 2's axis relates to
// it as named; joint 3 is skew to joint 2
std::vector<JointSpec> pair_case(const std::string& xyz2, const std::string& axis2) {
  return {{"0 0 0", "0.4 -0.5 0.6", "0 0 1", ""},
          {xyz2, "0 0 0", axis2, ""},
          {"0.2 0.1 0.3", "0.3 0.2 0.1", "1 0.5 0.2", ""}};
}

TEST(UrdfAxes, Skew) {
  const auto imp = check_small(tree_urdf(pair_case("0.3 0.2 0.1", "0 1 1")));
  const auto& dh = imp.model.joints[0].dh;
  EXPECT_NEAR(dh.a, 0.3, 1e-12);  // the common normal of z and (0, 1, 1)/sqrt 2 through (0.3, 0.2, 0.1)
  EXPECT_NEAR(std::abs(dh.alpha), kPi / 4, 1e-12);
  EXPECT_FALSE(imp.model.joints[1].mounted);
  EXPECT_FALSE(imp.model.joints[2].mounted);
}

TEST(UrdfAxes, Intersecting) {
  const auto imp = check_small(tree_urdf(pair_case("0 0 0.4", "2 0 0")));  // axis not normalised on purpose
  const auto& dh = imp.model.joints[0].dh;
  EXPECT_NEAR(dh.a, 0, 1e-12);
  EXPECT_NEAR(dh.d, 0.4, 1e-12);
  EXPECT_NEAR(std::abs(dh.alpha), kPi / 2, 1e-12);
}

TEST(UrdfAxes, Parallel) {
  const auto imp = check_small(tree_urdf(pair_case("0.4 0 0.1", "0 0 1")));
  const auto& dh = imp.model.joints[0].dh;
  EXPECT_NEAR(dh.a, 0.4, 1e-12);
  EXPECT_EQ(classify_twist(dh.alpha), Twist::Zero);
  EXPECT_NEAR(dh.d, 0.1, 1e-12);
}

TEST(UrdfAxes, AntiParallel) {
  const auto imp = check_small(tree_urdf(pair_case("0.4 0 0", "0 0 -1")));
  const auto& dh = imp.model.joints[0].dh;
  EXPECT_NEAR(dh.a, 0.4, 1e-12);
  EXPECT_EQ(classify_twist(dh.alpha), Twist::Pi);
}

TEST(UrdfAxes, Coincident) {
  const auto imp = check_small(tree_urdf(pair_case("0 0 0.3", "0 0 1")));
  const auto& dh = imp.model.joints[0].dh;
  EXPECT_NEAR(dh.a, 0, 1e-12);
  EXPECT_NEAR(dh.d, 0.3, 1e-12);
  EXPECT_EQ(classify_twist(dh.alpha), Twist::Zero);
}

TEST(UrdfAxes, CoincidentOpposite) {
  const auto imp = check_small(tree_urdf(pair_case("0 0 -0.2", "0 0 -1")));
  const auto& dh = imp.model.joints[0].dh;
  EXPECT_NEAR(dh.a, 0, 1e-12);
  EXPECT_EQ(classify_twist(dh.alpha), Twist::Pi);
}

TEST(UrdfAxes, NearlyParallelUsesAMount) {
  // 1e-7 rad apart, 0.1 m apart: the common normal lies ~1e6 m away, so the next joint gets a mount
  const auto imp = check_small(tree_urdf(pair_case("0.1 0 0", "1e-7 0 1")));
  EXPECT_TRUE(imp.model.joints[1].mounted);
  for (const auto& j : imp.model.joints) EXPECT_LT(std::abs(j.dh.d) + std::abs(j.dh.a), 10.0) << j.name;
}

// Axes 2e-9 rad to 0.05 rad apart, their origins 0.1 m apart, parallel and anti-parallel: up to 1e-4 rad
// the common normal's feet lie more than 10 m away, and the next joint gets a mount; at 0.05 rad, 2 m away,
// a DH row reaches it. (The closest points were found with 1 - cos^2 as the denominator, which rounds to 0
// at 1e-8 rad: from 2e-9 to 1e-8 the import failed with "DH parameters are not finite".)
TEST(UrdfAxes, AxesAlmostParallelImportAtEveryTilt) {
  for (const double tilt : {2e-9, 5e-9, 1e-8, 2e-8, 1e-6, 1e-4, 0.05}) {
    for (const char* z : {" 0 1", " 0 -1"}) {
      SCOPED_TRACE(std::to_string(tilt) + z);
      char axis[64];
      std::snprintf(axis, sizeof axis, "%.17g%s", tilt, z);
      const auto imp = check_small(tree_urdf(pair_case("0.1 0 0", axis)));
      EXPECT_EQ(imp.model.joints[1].mounted, tilt < 0.01);
      for (const auto& j : imp.model.joints) EXPECT_LT(std::abs(j.dh.d) + std::abs(j.dh.a), 10.0) << j.name;
    }
  }
}

TEST(UrdfAxes, BranchesMountsAndReRooting) {
  // l1 carries three chains: j2 (the DH continuation), j3 on l1's DH z axis (no mount), j4 off it (mount)
  const std::vector<JointSpec> joints{{"0.1 0 0.2", "0 0.3 0", "0 0 1", ""},
                                      {"0.3 0 0", "0 0 0", "0 1 0", "l1"},
                                      {"0.3 0.25 0", "0 0.2 0", "0 1 0", "l1"},
                                      {"0 0 0.3", "0 0 0.5", "1 0 0", "l1"},
                                      {"0.2 0 0", "0 0 0", "0 0 1", "l4"}};
  const auto imp = check_small(tree_urdf(joints));
  ASSERT_EQ(imp.model.joints.size(), 5u);
  EXPECT_FALSE(imp.model.joints[1].mounted);
  EXPECT_FALSE(imp.model.joints[2].mounted);  // j3 turns about the line of j2's axis
  EXPECT_TRUE(imp.model.joints[3].mounted);
  EXPECT_TRUE(imp.model.joints[0].mounted);  // the base frame's z is not j1's axis (rpy tilts it)
  // the same tree rooted at every link
  for (const char* root : {"l1", "l2", "l3", "l4", "l5"}) {
    SCOPED_TRACE(root);
    const auto r = check_small(tree_urdf(joints), root);
    EXPECT_EQ(r.model.base_link_name, root);
  }
}

TEST(UrdfAxes, FixedJointsMergeAndMasslessLinks) {
  const std::string xml = R"(<robot name="m">
  <link name="base"/>
  <link name="a"><inertial><mass value="2"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <link name="virtual"/>
  <link name="b"><inertial><origin xyz="0 0 0.2"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.01"/></inertial></link>
  <link name="tool"><inertial><origin xyz="0.1 0 0"/><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <joint name="q1" type="revolute"><parent link="base"/><child link="a"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="q2" type="continuous"><parent link="a"/><child link="virtual"/><origin xyz="0 0 0.3" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/></joint>
  <joint name="q3" type="continuous"><parent link="virtual"/><child link="b"/><axis xyz="1 0 0"/></joint>
  <joint name="weld" type="fixed"><parent link="b"/><child link="tool"/><origin xyz="0 0 0.4" rpy="0.3 0 0"/></joint>
</robot>)";
  const auto imp = check_small(xml);
  ASSERT_EQ(imp.model.joints.size(), 3u);
  EXPECT_EQ(imp.model.joints[1].body.mass, 0.0);         // the virtual link stays massless
  EXPECT_DOUBLE_EQ(imp.model.joints[2].body.mass, 1.5);  // the tool lumped into b
  check_small(xml, "tool");
}

// Random trees: random parents, origins and axes, with special relations (parallel, coincident,
// intersecting, anti-parallel axes) and fixed joints mixed in, each rooted at its root and elsewhere.
std::string random_tree_urdf(int links, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> pick(0, 9);
  const auto v3 = [&](double s) {
    std::ostringstream o;
    o.precision(17);
    o << s * u(rng) << " " << s * u(rng) << " " << s * u(rng);
    return o.str();
  };
  std::ostringstream x;
  x << "<robot name=\"random\">\n";
  for (int k = 0; k < links; ++k) {
    x << "<link name=\"r" << k << "\">";
    if (pick(rng) > 2)
      x << "<inertial><origin xyz=\"" << v3(0.2) << "\" rpy=\"" << v3(3) << "\"/><mass value=\"" << 1.5 + u(rng)
        << "\"/><inertia ixx=\"0.05\" ixy=\"0.004\" ixz=\"-0.003\" iyy=\"0.04\" iyz=\"0.002\" "
           "izz=\"0.06\"/></inertial>";
    x << "</link>\n";
  }
  for (int k = 1; k < links; ++k) {
    const int parent = std::uniform_int_distribution<int>(std::max(0, k - 4), k - 1)(rng);
    const int kind = pick(rng);
    std::string xyz = v3(0.3), rpy = v3(3), axis = v3(1);
    if (kind == 0) {
      rpy = "0 0 0";
      axis = "0 0 1";
      xyz = "0.2 0.1 0";
    }  // often parallel to a z neighbour
    if (kind == 1) {
      rpy = "0 0 0";
      axis = "0 0 -1";
      xyz = "0 0 0.3";
    }  // coincident, opposite
    if (kind == 2) {
      xyz = "0 0 0";
    }  // intersecting at the parent origin
    x << "<joint name=\"q" << k << "\" type=\"" << (kind == 3 ? "fixed" : "continuous") << "\"><parent link=\"r"
      << parent << "\"/><child link=\"r" << k << "\"/><origin xyz=\"" << xyz << "\" rpy=\"" << rpy << "\"/><axis xyz=\""
      << axis << "\"/></joint>\n";
  }
  x << "</robot>\n";
  return x.str();
}

TEST(UrdfAxes, RandomTrees) {
  std::mt19937 rng(2024);
  for (int t = 0; t < 12; ++t) {
    const std::string xml = random_tree_urdf(25, rng);
    SCOPED_TRACE(xml);
    check_small(xml);
    std::string root = "r";  // appended, not "r" + to_string(): GCC 12 warns falsely on that (-Wrestrict)
    root += std::to_string(5 + t);
    check_small(xml, root);
  }
}

// ---------------------------------------------------------------------------------------------------
// human36_isb.urdf reduced to the seed's 16 joints, rooted at the right foot

Q locked_others(const ::urdf::ModelInterface& m, const hu::Import& imp) {
  Q locked;
  for (const auto& [name, j] : m.joints_)
    if (std::find(imp.urdf_joints.begin(), imp.urdf_joints.end(), name) == imp.urdf_joints.end()) locked[name] = 0;
  return locked;
}

TEST(UrdfHuman36, SeedReductionAtTheRightFoot) {
  REQUIRE_FILE(shared_urdf("human36_isb.urdf"));
  const std::string file = shared_urdf("human36_isb.urdf"), xml = read_text(file);
  hu::ImportOptions opt;
  opt.root = "right_foot";
  opt.joints = hu::read_joint_map(std::string(HUMANDYN_URDF_TEST_DATA) + "/human36_seed.jointmap");
  opt.gravity = hu::gravity_for_up("y");
  const auto imp = hu::import_urdf(xml, opt, file);
  expect_inertials_match_xml(imp, xml);
  ASSERT_EQ(imp.model.joints.size(), 16u);
  for (int i = 0; i < 16; ++i) {
    EXPECT_EQ(imp.model.joints[std::size_t(i)].name, seed_joint_names[std::size_t(i)]);
    EXPECT_EQ(imp.model.joints[std::size_t(i)].parent, SeedShape::spec.parent[std::size_t(i)]);
  }
  EXPECT_TRUE(imp.reversed[0] && imp.reversed[3] && !imp.reversed[4] && !imp.reversed[12]);

  // the URDF's own kinematics and KDL's dynamics, the other 20 joints locked at 0
  const auto m = parse(xml);
  const Q locked = locked_others(*m, imp);
  EXPECT_LE(fk_error(imp, xml, locked, 100, nullptr), 1e-12);
  EXPECT_LE(id_error(imp, kdl_tree_at(*m, "right_foot", locked), locked, 1000), 1e-9);

  // static torque at the stance ankle = weight above it x horizontal lever of its centre of mass,
  // from the unreduced file: urdfdom poses in the right foot's frame (y up), every link but the foot's
  const AnyModel<double> model(imp.model);
  Data<AnyModel<double>> data(model);
  std::mt19937 rng(3);
  const double g0 = 9.81;
  double worst = 0, largest = 0;
  for (int t = 0; t < 50; ++t) {
    const State s = random_state(16, rng);
    Q q = locked;
    for (int i = 0; i < 16; ++i) q[imp.urdf_joints[std::size_t(i)]] = s.q[i];
    const auto poses = urdf_poses(*m, q);
    const P foot_inv = poses.at("right_foot").inverse();
    double mass = 0;
    Vector3d mc = Vector3d::Zero();
    for (const auto& [name, l] : m->links_) {
      if (!l->inertial || name == "right_foot" || name == "right_foot_virtual") continue;
      const auto& in = l->inertial;
      mass += in->mass;
      mc += in->mass *
            (foot_inv * poses.at(name) * Vector3d(in->origin.position.x, in->origin.position.y, in->origin.position.z));
    }
    const Vector3d com = mc / mass;
    const auto ankle = m->getJoint("right_ankle_Z");
    const P J = foot_inv * poses.at(ankle->parent_link_name) * to_pose(ankle->parent_to_joint_origin_transform);
    const Vector3d u = (J.R * Vector3d(ankle->axis.x, ankle->axis.y, ankle->axis.z)).normalized();
    const Vector3d up = Vector3d::UnitY();
    ASSERT_NEAR(u.dot(up), 0, 1e-12) << "the ankle axis is horizontal";
    const double lever = (com - J.p).dot(up.cross(u));  // horizontal distance, signed, across the axis
    const double expected = -mass * g0 * lever;
    gravity_torques(model, data, s.q);
    EXPECT_NEAR(data.tau[0], expected, 1e-9 * std::max(1.0, std::abs(expected)));
    worst = std::max(worst, std::abs(data.tau[0] - expected));
    largest = std::max(largest, std::abs(expected));
    EXPECT_GT(std::abs(lever), 1e-4);
  }
  std::printf(
      "[ measured ] human36 seed reduction at the right foot: stance-ankle torque %.1e N m off weight x lever "
      "(largest %.0f N m, 50 poses)\n",
      worst, largest);
  std::string why;
  // it does not run as the compile-time seed shape (docs/urdf.md says why): the stance ankle's twist
  const auto human = hu::try_human_model(imp.model, &why);
  EXPECT_FALSE(human.has_value());
  EXPECT_NE(why.find("joint 1 'r_ankle_pitch' (link 'right_lowerleg'): twist alpha = -3.14"), std::string::npos) << why;
}

TEST(UrdfHuman36, RunsInFloat) {
  REQUIRE_FILE(shared_urdf("human36_isb.urdf"));
  hu::ImportOptions opt;
  opt.gravity = hu::gravity_for_up("y");
  const auto imp = hu::import_urdf_file(shared_urdf("human36_isb.urdf"), opt);
  const AnyModel<double> md(imp.model);
  const AnyModel<float> mf(imp.model.cast<float>());
  Data<AnyModel<double>> dd(md);
  Data<AnyModel<float>> df(mf);
  std::mt19937 rng(9);
  for (int t = 0; t < 100; ++t) {
    const State s = random_state(md.size(), rng);
    rnea<Terms::Full>(md, dd, s.q, s.qd, s.qdd);
    const Eigen::VectorXf q = s.q.cast<float>(), qd = s.qd.cast<float>(), qdd = s.qdd.cast<float>();
    rnea<Terms::Full>(mf, df, q, qd, qdd);
    const double scale = std::max(1.0, dd.tau.cwiseAbs().maxCoeff());
    EXPECT_LE((df.tau.cast<double>() - dd.tau).cwiseAbs().maxCoeff(), 1e-4 * scale);
  }
}

// ---------------------------------------------------------------------------------------------------
// Round trip: model -> URDF -> model

void expect_same_description(const ModelDescription<double>& a, const ModelDescription<double>& b) {
  ASSERT_EQ(a.joints.size(), b.joints.size());
  const auto near = [](const auto& x, const auto& y) { return (x - y).cwiseAbs().maxCoeff() <= 1e-12; };
  for (std::size_t i = 0; i < a.joints.size(); ++i) {
    const auto &x = a.joints[i], &y = b.joints[i];
    SCOPED_TRACE(x.name);
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.link_name, y.link_name);
    EXPECT_EQ(x.parent, y.parent);
    EXPECT_EQ(x.mounted, y.mounted);
    if (x.mounted && y.mounted) {
      EXPECT_TRUE(near(x.mount.R, y.mount.R) && near(x.mount.p, y.mount.p));
    }
    EXPECT_NEAR(x.dh.a, y.dh.a, 1e-12);
    EXPECT_NEAR(std::remainder(x.dh.alpha - y.dh.alpha, 2 * kPi), 0, 1e-12);
    EXPECT_NEAR(x.dh.d, y.dh.d, 1e-12);
    EXPECT_NEAR(std::remainder(x.dh.theta - y.dh.theta, 2 * kPi), 0, 1e-12);
    EXPECT_NEAR(x.body.mass, y.body.mass, 1e-12);
    EXPECT_TRUE(near(x.body.com, y.body.com));
    EXPECT_TRUE(near(x.body.inertia, y.body.inertia));
  }
  EXPECT_NEAR(a.base_body.mass, b.base_body.mass, 1e-12);
  EXPECT_TRUE(near(a.base_body.com, b.base_body.com));
  EXPECT_TRUE(near(a.base_body.inertia, b.base_body.inertia));
}

// torques of two descriptions of one body on random states
double torque_difference(const ModelDescription<double>& a, const ModelDescription<double>& b, int trials) {
  const AnyModel<double> ma(a), mb(b);
  Data<AnyModel<double>> da(ma), db(mb);
  std::mt19937 rng(5);
  double err = 0;
  for (int t = 0; t < trials; ++t) {
    const State s = random_state(ma.size(), rng);
    rnea<Terms::Full>(ma, da, s.q, s.qd, s.qdd);
    rnea<Terms::Full>(mb, db, s.q, s.qd, s.qdd);
    err = std::max(err, (da.tau - db.tau).cwiseAbs().maxCoeff());
  }
  return err;
}

hu::Import reimport(const ModelDescription<double>& d) {
  hu::ImportOptions opt;
  opt.gravity = d.base_pose.R.transpose() * d.gravity;
  const std::string xml = hu::to_urdf(d);
  auto imp = hu::import_urdf(xml, opt, "exported.urdf");
  expect_inertials_match_xml(imp, xml);
  return imp;
}

TEST(UrdfRoundTrip, DefaultHuman) {
  const auto d = human_description(default_parameters());
  const std::string xml = hu::to_urdf(d);
  const auto back = reimport(d);
  expect_same_description(d, back.model);
  const double dtau = torque_difference(d, back.model, 1000);
  EXPECT_LE(dtau, 1e-9);
  std::printf("[ measured ] default human -> URDF -> model: torques %.1e N m apart on 1000 states\n", dtau);
  std::string why;
  EXPECT_TRUE(hu::try_human_model(back.model, &why).has_value()) << why;
  // the exported file as any URDF tool reads it: kdl_parser's tree gives the model's torques
  hu::ImportOptions opt;
  opt.gravity = d.base_pose.R.transpose() * d.gravity;
  const auto again = hu::import_urdf(xml, opt, "exported.urdf");
  EXPECT_LE(id_error(again, kdl_parser_tree(xml), {}, 1000), 1e-9);
  EXPECT_LE(fk_error(again, xml, {}, 100, nullptr), 1e-12);
}

// A second joint turned nearly anti-parallel to the first (rpy 3.14159: 2.65e-6 rad off), its common
// normal metres away: the export reads back to the same model. (Its own file was refused, "the DH frame is
// not reachable by a DH row", the common normal's foot found 1e-5 m off by the rounding of 1 - cos^2.)
TEST(UrdfRoundTrip, NearlyAntiParallelAxes) {
  const std::string xml = R"(<?xml version="1.0"?>
<robot name="np">
  <link name="base"/>
  <link name="l1"><inertial><origin xyz="0.2 0.1 0"/><mass value="1"/><inertia ixx="0.01" ixy="0.001" ixz="0" iyy="0.02" iyz="0" izz="0.015"/></inertial></link>
  <link name="l2"><inertial><origin xyz="0.2 0 0.05"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="l3"><inertial><origin xyz="0.1 0 0"/><mass value="0.5"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="j1" type="continuous"><parent link="base"/><child link="l1"/><origin xyz="0 0 1" rpy="0.3 0 0"/><axis xyz="0 1 0"/></joint>
  <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/><origin xyz="0.5 0 0" rpy="3.14159 0 0"/><axis xyz="0 1 0"/></joint>
  <joint name="j3" type="continuous"><parent link="l2"/><child link="l3"/><origin xyz="0.3 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/></joint>
</robot>
)";
  const auto first = check_small(xml);
  const auto back = reimport(first.model);
  expect_same_description(first.model, back.model);
  EXPECT_LE(torque_difference(first.model, back.model, 200), 1e-9);
}

// The exporter's own names read back: a chain's tip joint is named after its last joint and kept apart
// from every joint (it was '<link>_tip_joint', and a joint of that name made the export refuse itself;
// here the chain's last joint is 'hand' and another joint is 'hand_tip', so the tip joint is 'hand_tip_');
// link names with a comma, a quote, blanks around them, a tab or a line feed are written so that they
// read back as they were; a control character XML cannot carry is an error, not a broken file.
TEST(UrdfRoundTrip, ExportedNamesReadBack) {
  const std::string one = R"(<robot name="p1"><link name="base"/>
<link name="arm"><inertial><origin xyz="0.5 0 0"/><mass value="2"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
<link name="hand"><inertial><origin xyz="0.1 0 0"/><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.002"/></inertial></link>
<joint name="arm_tip_joint" type="continuous"><parent link="base"/><child link="arm"/><origin xyz="0 0 1"/><axis xyz="0 1 0"/></joint>
<joint name="hand_tip" type="continuous"><parent link="arm"/><child link="hand"/><origin xyz="1 0 0"/><axis xyz="0 0 1"/></joint>
</robot>
)";
  auto d = hu::import_urdf(one, {}, "one.urdf").model;
  d.joints[0].name = "hand_tip";  // the name the tip joint of the chain ending at 'hand' would take first
  d.joints[1].name = "hand";
  for (const std::string link : {"ar,m", "a\"rm", " arm ", "ar\tm", "ar\nm", "ar\r\nm", "hand_tip"}) {
    SCOPED_TRACE(link);
    d.joints[0].link_name = link;
    const auto back = reimport(d);
    expect_same_description(d, back.model);
    EXPECT_EQ(back.model.joints[0].link_name, link);
  }
  d.joints[0].link_name = "ar\x01m";
  try {
    hu::to_urdf(d);
    ADD_FAILURE() << "no error";
  } catch (const hu::Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "'ar<U+0001>m' cannot be written into a URDF: the name holds a control character, <U+0001>");
  }
  d.joints[0].link_name = "ar\xEF\xBF\xBEm";  // U+FFFE
  try {
    hu::to_urdf(d);
    ADD_FAILURE() << "no error";
  } catch (const hu::Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "'ar<U+FFFE>m' cannot be written into a URDF: the name holds a noncharacter, <U+FFFE>");
  }
  d.joints[0].link_name = "ar\xFFm";  // no UTF-8
  try {
    hu::to_urdf(d);
    ADD_FAILURE() << "no error";
  } catch (const hu::Error& e) {
    EXPECT_EQ(std::string(e.what()), "'ar<0xFF>m' cannot be written into a URDF: the name is not UTF-8 (byte <0xFF>)");
  }
  // the model's name: with "--", which no XML comment may hold (it is written in the robot's attribute alone),
  // and empty (once written as "humandyn")
  d.joints[0].link_name = "arm";
  for (const std::string name : {"arm--v2-", ""}) {
    d.name = name;
    const std::string xml = hu::to_urdf(d);
    const std::size_t comment = xml.find("<!--"), end = xml.find("-->", comment);
    ASSERT_NE(end, std::string::npos);
    EXPECT_EQ(xml.substr(comment + 4, end - comment - 4).find("--"), std::string::npos) << xml.substr(0, end + 3);
    EXPECT_EQ(reimport(d).model.name, name);
  }
}

TEST(UrdfRoundTrip, ImportedModelsWithMounts) {
  REQUIRE_FILE(shared_urdf("ur5_robot.urdf"));
  for (const auto& [file, root] : {std::pair<std::string, std::string>{"ur5_robot.urdf", ""},
                                   {"ur5_robot.urdf", "ee_link"},
                                   {"human36_isb.urdf", "right_foot"},
                                   {"simple_humanoid.urdf", ""}}) {
    SCOPED_TRACE(file + " at " + root);
    hu::ImportOptions opt;
    opt.root = root;
    const auto first = hu::import_urdf_file(shared_urdf(file), opt);
    const auto back = reimport(first.model);
    expect_same_description(first.model, back.model);
    EXPECT_LE(torque_difference(first.model, back.model, 200), 1e-9);
  }
}

// ---------------------------------------------------------------------------------------------------
// Bad input: each error names its element

std::string error_of(const std::string& xml, const hu::ImportOptions& opt = {}) {
  try {
    hu::import_urdf(xml, opt, "bad.urdf");
  } catch (const hu::Error& e) {
    return e.what();
  }
  return "no error";
}

void expect_error(const std::string& xml, std::initializer_list<const char*> parts, const hu::ImportOptions& opt = {}) {
  const std::string what = error_of(xml, opt);
  for (const char* p : parts) EXPECT_NE(what.find(p), std::string::npos) << "'" << p << "' not in: " << what;
}

const char* kLimit = R"(<limit lower="-1" upper="1" effort="1" velocity="1"/>)";

std::string two_links(const std::string& joint_body, const std::string& link_a_inside = "") {
  return "<robot name=\"r\">\n<link name=\"a\">" + link_a_inside + "</link>\n<link name=\"b\"/>\n" + joint_body +
         "\n</robot>\n";
}

// urdfdom passes over the names it does not know, so a misspelt element or attribute would silently leave
// its numbers out (an <Inertial> left the thigh massless, an <orgin> put the joint at the parent's
// origin). Each is refused with its line and the name it resembles, any unknown name in an element that
// holds numbers alone, and an unexpanded xacro file; extensions pass.
TEST(UrdfErrors, MisspeltNamesAreRefusedAndExtensionsPass) {
  const std::string joint =
      std::string(R"(<joint name="j" type="revolute"><parent link="a"/><child link="b"/>)") + kLimit + "</joint>";
  const std::string inertial = R"(<inertial><origin xyz="0 0 -0.1"/><mass value="2"/>)"
                               R"(<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>)";
  ASSERT_EQ(error_of(two_links(joint, inertial)), "no error");
  const auto with = [](std::string text, const std::string& from, const std::string& to) {
    return text.replace(text.find(from), from.size(), to);
  };
  expect_error(two_links(joint, with(with(inertial, "<inertial>", "<Inertial>"), "</inertial>", "</Inertial>")),
               {"bad.urdf:2: link 'a': <Inertial> is not an element of <link>: is it <inertial>? (URDF's are "
                "inertial, visual or collision)"});
  expect_error(two_links(joint, with(with(inertial, "<inertial>", "<intertial>"), "</inertial>", "</intertial>")),
               {"bad.urdf:2: link 'a': <intertial> is not an element of <link>: is it <inertial>?"});
  expect_error(two_links(joint, with(inertial, "origin xyz", "origin xzy")),
               {"bad.urdf:2: link 'a': <origin> has an attribute xzy that URDF does not give it: is it xyz?"});
  expect_error(two_links(joint, with(inertial, "origin xyz", "origin pos")),
               {"bad.urdf:2: link 'a': <origin> has an attribute pos that URDF does not give it (URDF's are xyz or "
                "rpy)"});
  expect_error(two_links(joint, with(inertial, "<mass value=\"2\"/>", "<mass value=\"2\"/><com xyz=\"0 0 0\"/>")),
               {"link 'a': <com> is not an element of <inertial> (URDF's are origin, mass or inertia)"});
  expect_error(two_links(joint, with(inertial, "ixx=", "Ixx=")), {"<inertia> has an attribute Ixx", "is it ixx?"});
  expect_error(two_links(joint, with(inertial, "value=", "val=")), {"<mass> has an attribute val"});
  expect_error(two_links(with(joint, "<parent", "<orgin xyz=\"0 0 -0.3\"/><parent")),
               {"bad.urdf:4: joint 'j': <orgin> is not an element of <joint>: is it <origin>?"});
  expect_error(two_links(with(joint, "<parent", "<axis xzy=\"0 1 0\"/><parent")),
               {"bad.urdf:4: joint 'j': <axis> has an attribute xzy that URDF does not give it: is it xyz?"});
  expect_error(two_links(with(joint, "effort=", "efort=")),
               {"joint 'j': <limit> has an attribute efort", "is it effort?"});
  expect_error(two_links(with(joint, "<child link", "<child lnk=\"b\" link")), {"<child> has an attribute lnk"});
  expect_error(
      "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<link name=\"a\"/>\n"
      "<xacro:macro name=\"m\"><link name=\"b\"/></xacro:macro>\n</robot>\n",
      {"bad.urdf:3: <xacro:macro>: a xacro file, which needs expanding into URDF first"});
  expect_error(
      "<robot name=\"r\" xmlns:x=\"http://www.ros.org/wiki/xacro\">\n<link name=\"a\">\n"
      "<x:insert_block name=\"m\"/></link>\n</robot>\n",
      {"bad.urdf:3: <x:insert_block>: a xacro file"});
  // a misspelling by two edits, or of a name that belongs elsewhere, or with a look-alike letter
  expect_error(two_links(with(joint, "<parent", "<orig xyz=\"0 0 -0.3\"/><parent")),
               {"<orig> is not an element of <joint>: is it <origin>?"});
  expect_error(two_links(with(joint, "<parent", "<asix xyz=\"0 1 0\"/><parent")),
               {"<asix> is not an element of <joint>: is it <axis>?"});
  expect_error(two_links(with(joint, "<parent", "<\xD0\xB0xis xyz=\"0 1 0\"/><parent")),  // a Cyrillic a
               {"is it <axis>?"});
  expect_error(two_links(joint, with(with(inertial, "<inertial>", "<interia>"), "</inertial>", "</interia>")),
               {"link 'a': <interia> is not an element of <link>: is it <inertia>, which URDF puts elsewhere?"});
  expect_error(
      two_links(joint, "<origin xyz=\"0 0 -0.1\"/>" + inertial),
      {"link 'a': <origin> is not an element of <link>: URDF puts it elsewhere (URDF's are inertial, visual or "
       "collision)"});
  // what tutorials' robots write, which changes no number: an axis's zero rpy, a named inertial, a typed
  // parent; a non-zero rpy on an axis is refused (urdfdom would not turn the axis by it)
  EXPECT_EQ(error_of(two_links(with(joint, "<parent", "<axis rpy=\"0 0 0\" xyz=\"0 1 0\"/><parent"),
                               with(inertial, "<inertial>", "<inertial name=\"body_inertial\">"))),
            "no error");
  EXPECT_EQ(error_of(two_links(with(joint, "<parent link", "<parent type=\"link\" link"))), "no error");
  expect_error(two_links(with(joint, "<parent", "<axis rpy=\"0 0 1.57\" xyz=\"0 1 0\"/><parent")),
               {"joint 'j': <axis rpy=\"0 0 1.57\">: urdfdom reads no rpy on an axis"});
  expect_error("<robot name=\"r\">\n<link name=\"a\"/>\n<jiont name=\"j\"/>\n</robot>\n",
               {"bad.urdf:3: <robot>: <jiont> is not an element of <robot>: is it <joint>?"});
  // extensions pass: a namespaced element in a joint, PyBullet's <contact> in a link, <gazebo> at the top
  EXPECT_EQ(error_of(two_links(with(joint, "<parent", "<drake:rotor_inertia value=\"1\"/><parent"),
                               inertial + "<contact><lateral_friction value=\"1\"/></contact>")),
            "no error");
  EXPECT_EQ(error_of(with(two_links(joint), "</robot>",
                          "<gazebo reference=\"a\"><selfCollide>1</selfCollide></gazebo></robot>")),
            "no error");
  // a number a double holds only as 0 reads as no number at all
  expect_error(two_links(joint, with(inertial, "value=\"2\"", "value=\"2e-400\"")),
               {"bad.urdf:2: link 'a': <mass value=\"2e-400\">: '2e-400' is out of the range of a double: too small, "
                "it would read as 0"});
  expect_error(two_links(joint, with(inertial, "ixy=\"0\"", "ixy=\"1e-400\"")), {"'1e-400' is out of the range"});
}

TEST(UrdfErrors, ReferencesAreReadOnlyWhereXmlReadsThem) {
  // in a comment, a CDATA section or a processing instruction, "&#0;" is text: the file is read
  const std::string body = R"(<joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>)";
  for (const char* aside : {"<!-- &#0; and &# -->", "<![CDATA[ &#0; <x> ]]>"}) {
    SCOPED_TRACE(aside);
    EXPECT_EQ(error_of(two_links(body, aside)), "no error");
  }
  EXPECT_EQ(error_of("<?note &#0; ?>\n" + two_links(body)), "no error");
  EXPECT_EQ(error_of("<!DOCTYPE robot SYSTEM \"&#0;\">\n" + two_links(body)), "no error");
  // a '<' in an attribute value is not XML: it cannot open a comment that hides a reference
  expect_error(two_links(R"(<joint name="j&#0;" y="-->" type="continuous"><parent link="a"/><child link="b"/></joint>)",
                         "<x a=\"<!--\"/>"),
               {"bad.urdf:2: not XML: a '<' in an attribute value"});
  // in attributes and text it is read: a character XML allows is the character
  EXPECT_EQ(hu::import_urdf(two_links(R"(<joint name="j&#x41;&#66;" type="continuous"><parent link="a"/>)"
                                      R"(<child link="b"/></joint>)"))
                .model.joints[0]
                .name,
            "jAB");
}

TEST(UrdfErrors, NamesTheElement) {
  expect_error("this is not xml <", {"bad.urdf:", "not XML"});
  expect_error("<robot name=\"r\">\n<link name=\"a\">\n<?pi x?>\n</link>\n</robot>",
               {"bad.urdf:3: not XML: a <?...?> declaration or processing instruction stands after the document's "
                "start",
                "(XML_ERROR_PARSING_DECLARATION)"});
  expect_error("<robot name=\"r\">\n<link name=\"a\">\n\n</lnk>\n</robot>",
               {"bad.urdf:2: not XML: the element opened on this line is closed by an end tag of another name"});
  EXPECT_EQ(error_of(""), "bad.urdf: not XML: there is no element (XML_ERROR_EMPTY_DOCUMENT)");
  // what XML does not allow and the XML reader takes: a reference to U+0000 cuts a name short
  expect_error("<robot name=\"r\">\n<link name=\"b&#0;x\"/>\n</robot>",
               {"bad.urdf:2: not XML: the character reference &#0; names no character XML allows"});
  expect_error("<robot name=\"r\">\n\n<link name=\"b&#x110000;\"/>\n</robot>",
               {"bad.urdf:3: not XML: the character reference &#x110000; names no character"});
  expect_error("<robot name=\"r\">\n<link name=\"b\x01\"/>\n</robot>",
               {"bad.urdf:2: not XML: a control character, <U+0001>, which XML does not allow"});
  expect_error("<robot name=\"r\">\n<link name=\"b&#99999999999999999999;\"/>\n</robot>",
               {"bad.urdf:2: not XML: the character reference &#99999999999999999999; names no character"});
  expect_error("<?xml version=\"1.0\"?>\n<model name=\"x\"/>", {"no <robot> element", "<model>"});
  expect_error("<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n</robot>",
               {"two root links", "'a' (line 2)", "'b' (line 3)"});
  expect_error(R"(<robot name="r">
<link name="root"/><link name="a"/><link name="b"/>
<joint name="j0" type="fixed"><parent link="root"/><child link="x"/></joint>
</robot>)",
               {"bad.urdf:3: joint 'j0'", "child link 'x' is not defined"});
  expect_error(R"(<robot name="r">
<link name="root"/>
<link name="a"/>
<link name="b"/>
<joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
<joint name="ba" type="fixed"><parent link="b"/><child link="a"/></joint>
</robot>)",
               {"cycle", "joint '"});
  expect_error(
      two_links(R"(<joint name="j" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0 0"/></joint>)"),
      {"bad.urdf:4: joint 'j'", "zero axis"});
  expect_error(
      two_links(R"(<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>)",
                R"(<inertial><mass value="-2"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>)"),
      {"link 'a'", "negative mass"});
  expect_error(
      two_links(R"(<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>)",
                R"(<inertial><mass value="2"/><inertia ixx="-1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>)"),
      {"bad.urdf:2: link 'a'", "not positive semidefinite"});
  expect_error(
      two_links(R"(<joint name="j" type="fixed"><parent link="a"/><child link="b"/><origin xyz="0 nan 0"/></joint>)"),
      {"bad.urdf:4: joint 'j'", "'nan' is not a finite number"});
  expect_error(
      two_links(std::string(
                    R"(<joint name="slide" type="prismatic"><parent link="a"/><child link="b"/><axis xyz="1 0 0"/>)") +
                kLimit + "</joint>"),
      {"joint 'slide'", "prismatic joints are not supported"});
  expect_error(two_links(R"(<joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>)"),
               {"no link 'z'"}, hu::ImportOptions{"z", std::nullopt, Vector3d(0, 0, -9.81)});
}

TEST(UrdfErrors, JointTypesAndStructure) {
  const std::string three = R"(<robot name="r">
<link name="a"/>
<link name="b"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
<link name="c"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
<joint name="hinge" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 1 0"/></joint>
<joint name="other" type="TYPE"><parent link="b"/><child link="c"/><origin xyz="0.3 0 0"/><axis xyz="1 0 0"/>LIMIT MIMIC</joint>
</robot>)";
  const auto with = [&](const std::string& type, bool mimic) {
    std::string x = three;
    x.replace(x.find("TYPE"), 4, type);
    x.replace(x.find("LIMIT"), 5, kLimit);
    x.replace(x.find("MIMIC"), 5, mimic ? "<mimic joint=\"hinge\" multiplier=\"2\"/>" : "");
    return x;
  };
  expect_error(with("floating", false), {"bad.urdf:6: joint 'other'", "floating joints are not supported"});
  expect_error(with("planar", false), {"bad.urdf:6: joint 'other'", "planar joints are not supported"});
  expect_error(with("revolute", true), {"bad.urdf:6: joint 'other'", "mimic joints are not supported"});
  // each is accepted once a joint map locks it; a locked prismatic joint slides its link out
  hu::ImportOptions opt;
  opt.joints = hu::parse_joint_map("hinge\nother = 0.25\n", "lock.map");
  const std::string slider = with("prismatic", false);
  const auto imp = hu::import_urdf(slider, opt);
  ASSERT_EQ(imp.model.joints.size(), 1u);
  EXPECT_DOUBLE_EQ(imp.model.joints[0].body.mass, 2.0);
  ASSERT_EQ(imp.links.size(), 3u);
  EXPECT_EQ(imp.links[1].joint, 0);
  EXPECT_EQ(imp.links[2].joint, 0);
  const P b_to_c = imp.links[1].pose.inverse() * imp.links[2].pose;  // origin 0.3 along x, slid 0.25 along x
  EXPECT_LE((b_to_c.p - Vector3d(0.55, 0, 0)).norm(), 1e-15);
  opt.joints = hu::parse_joint_map("hinge\n", "lock.map");
  EXPECT_EQ(hu::import_urdf(with("revolute", true), opt).model.joints.size(), 1u);
  EXPECT_EQ(hu::import_urdf(with("floating", false), opt).model.joints.size(), 1u);
  opt.joints = hu::parse_joint_map("hinge\nother = 0.1\n", "lock.map");
  expect_error(with("floating", false), {"lock.map:2: joint 'other'", "can only be locked at 0"}, opt);
  expect_error(with("fixed", false), {"lock.map:2: joint 'other'", "a fixed joint can only be locked at 0"}, opt);
  opt.joints = hu::parse_joint_map("hinge\nother = 0\n", "lock.map");  // (at 0: as it is)
  EXPECT_EQ(hu::import_urdf(with("fixed", false), opt).model.joints.size(), 1u);
  opt.joints = hu::parse_joint_map("hinge\nhinge\n", "lock.map");
  expect_error(with("revolute", false), {"lock.map:2: joint 'hinge'", "listed twice"}, opt);
  // structure
  expect_error(R"(<robot name="r">
<link name="a"/><link name="b"/>
<link name="a"/>
</robot>)",
               {"bad.urdf:3: link 'a'", "used twice"});
  expect_error(R"(<robot name="r">
<link name="a"/><link name="b"/><link name="c"/>
<joint name="j1" type="fixed"><parent link="a"/><child link="c"/></joint>
<joint name="j2" type="fixed"><parent link="b"/><child link="c"/></joint>
</robot>)",
               {"bad.urdf:4: joint 'j2'", "link 'c' already has a parent joint, 'j1' (line 3)"});
  expect_error(R"(<robot name="r">
<link name="a"/><link name="b"/>
<joint name="j" type="continuous"><parent link="a"/><child link="b"/><origin xyz="0 0 1e999"/></joint>
</robot>)",
               {"bad.urdf:3: joint 'j'", "not a finite number"});
  expect_error(R"(<robot name="r">
<link name="a"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="3"/></inertial></link>
</robot>)",
               {"bad.urdf:2: link 'a'", "triangle inequality"});
  expect_error(R"(<robot name="r">
<link name="a"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="abc"/></inertial></link>
</robot>)",
               {"bad.urdf:2: link 'a'", "'abc' is not a number"});
}

TEST(UrdfErrors, JointMap) {
  const std::string xml = two_links(R"(<joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>)");
  hu::ImportOptions opt;
  opt.joints = hu::parse_joint_map("# map\nj  hinge\nghost\n", "my.map");
  expect_error(xml, {"my.map:3: joint 'ghost'", "no such joint"}, opt);
  opt.joints = hu::parse_joint_map("j hinge\n", "my.map");
  EXPECT_EQ(hu::import_urdf(xml, opt).model.joints.at(0).name, "hinge");
  EXPECT_THROW(hu::parse_joint_map("j = abc\n", "my.map"), hu::Error);
  EXPECT_THROW(hu::parse_joint_map("j a b c\n", "my.map"), hu::Error);
}

// Two model joints with one name would head the same CSV columns: the map's line says which
TEST(UrdfErrors, AModelNameGivenTwiceNamesTheMapLine) {
  const std::string xml = R"(<robot name="r">
<link name="base"/><link name="a"/><link name="b"/>
<joint name="j1" type="continuous"><parent link="base"/><child link="a"/><axis xyz="0 1 0"/></joint>
<joint name="j2" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 1 0"/></joint>
</robot>)";
  hu::ImportOptions opt;
  opt.joints = hu::parse_joint_map("j1 x\nj2 x\n", "dup.map");
  const std::string what = error_of(xml, opt);
  EXPECT_EQ(what.find("bad.urdf"), std::string::npos) << what;
  expect_error(xml, {"dup.map:2: joint 'j2'", "model name 'x' is already given to joint 'j1' (line 1)"}, opt);
  // a renamed joint taking another's URDF name
  opt.joints = hu::parse_joint_map("j1 j2\n# j2 keeps its name\nj2\n", "dup.map");
  expect_error(xml, {"dup.map:3: joint 'j2'", "model name 'j2' is already given to joint 'j1' (line 1)"}, opt);
  // swapping two names is fine
  opt.joints = hu::parse_joint_map("j1 j2\nj2 j1\n", "swap.map");
  const auto imp = hu::import_urdf(xml, opt);
  ASSERT_EQ(imp.model.joints.size(), 2u);
  EXPECT_EQ(imp.model.joints[0].name, "j2");
  EXPECT_EQ(imp.model.joints[1].name, "j1");
}

// A model without joints cannot be read back (the model JSON reader needs one): refused at import
TEST(UrdfErrors, NoModelJointIsAnError) {
  const std::string xml = two_links(R"(<joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>)");
  hu::ImportOptions opt;
  opt.joints = hu::parse_joint_map("", "empty.map");
  expect_error(xml, {"empty.map: the joint map leaves no model joint", "every joint of bad.urdf is locked"}, opt);
  opt.joints = hu::parse_joint_map("j = 0.5\n", "lock.map");
  expect_error(xml, {"lock.map: the joint map leaves no model joint"}, opt);
  expect_error(two_links(R"(<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>)"),
               {"bad.urdf: no revolute or continuous joint"});
  expect_error("<robot name=\"r\">\n<link name=\"a\"/>\n</robot>\n", {"bad.urdf: no revolute or continuous joint"});
}

// ---------------------------------------------------------------------------------------------------
// The independent read on every URDF the tests have: the test data, the third-party files and the
// failing inputs of ../shared/cases, each at its root and at its last link

std::vector<std::string> urdf_files_in(const std::filesystem::path& dir) {
  std::vector<std::string> files;
  if (std::filesystem::exists(dir))
    for (const auto& f : std::filesystem::recursive_directory_iterator(dir))
      if (f.path().extension() == ".urdf") files.push_back(f.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

std::string shared_case(const std::string& name) { return std::string(HUMANDYN_SHARED_DATA) + "/../cases/" + name; }

TEST(UrdfInertials, EveryFileMatchesAnIndependentRead) {
  std::vector<std::string> files = urdf_files_in(HUMANDYN_URDF_TEST_DATA);
  const auto shared = urdf_files_in(std::string(HUMANDYN_SHARED_DATA) + "/urdf");
  const auto cases = urdf_files_in(shared_case(""));
  if (shared.empty())
    std::printf("[  SKIPPED ] %s/urdf is absent: third-party files not checked\n", HUMANDYN_SHARED_DATA);
  if (cases.empty()) std::printf("[  SKIPPED ] %s is absent: the shared cases not checked\n", shared_case("").c_str());
  files.insert(files.end(), shared.begin(), shared.end());
  files.insert(files.end(), cases.begin(), cases.end());
  int imported = 0, refused = 0;
  for (const auto& file : files) {
    SCOPED_TRACE(file);
    const std::string xml = read_text(file);
    hu::Import imp;
    try {
      imp = hu::import_urdf(xml, {}, file);
    } catch (const hu::Error&) {
      ++refused;  // refused inputs are tested for their messages elsewhere
      continue;
    }
    ++imported;
    expect_inertials_match_xml(imp, xml);
    hu::ImportOptions at_last;
    at_last.root = imp.links.back().link;
    expect_inertials_match_xml(hu::import_urdf(xml, at_last, file), xml);
  }
  std::printf("[ measured ] independent inertial read: %d files imported and matched, %d refused\n", imported, refused);
  EXPECT_GT(imported, 0);
}

// The messages of the failures `check` reports, intercepted (so that a test can see a check fail).
template <class F>
std::string failures_of(F check) {
  ::testing::TestPartResultArray results;
  {
    ::testing::ScopedFakeTestPartResultReporter reporter(
        ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &results);
    check();
  }
  std::string all;
  for (int i = 0; i < results.size(); ++i) all += std::string(results.GetTestPartResult(i).message()) + "\n";
  return all;
}

// The check sees what a parser that drops data would give: a mass read as 0, products of inertia as 0.
TEST(UrdfInertials, TheIndependentReadSeesSilentZeros) {
  const std::string xml = tree_urdf({{"0 0 0.1", "0 0 0", "0 0 1", ""}, {"0.2 0 0", "0 0 0", "0 1 0", ""}});
  const auto imp = hu::import_urdf(xml);
  expect_inertials_match_xml(imp, xml);
  auto massless = imp;
  massless.model.joints[0].body.mass = 0;
  EXPECT_NE(failures_of([&] { expect_inertials_match_xml(massless, xml); }).find("body.mass"), std::string::npos);
  auto principal_only = imp;
  auto& I = principal_only.model.joints[1].body.inertia;
  I = I.diagonal().asDiagonal().toDenseMatrix().eval();
  EXPECT_NE(failures_of([&] { expect_inertials_match_xml(principal_only, xml); }).find("about_origin"),
            std::string::npos);
}

// ---------------------------------------------------------------------------------------------------
// ../shared/cases/urdf-inertial-read: an inertial urdfdom cannot read is an error naming file, line and
// link; the body written in full gives the authored torque

std::string import_error(const std::string& file, const hu::ImportOptions& opt = {}) {
  try {
    hu::import_urdf_file(file, opt);
  } catch (const hu::Error& e) {
    return e.what();
  }
  return "no error";
}

void expect_all(const std::string& what, std::initializer_list<const char*> parts) {
  for (const char* p : parts) EXPECT_NE(what.find(p), std::string::npos) << "'" << p << "' not in: " << what;
}

TEST(UrdfCases, LegFullGivesTheAuthoredHipTorque) {
  REQUIRE_FILE(shared_case("urdf-inertial-read/leg_full.urdf"));
  const auto imp = hu::import_urdf_file(shared_case("urdf-inertial-read/leg_full.urdf"));
  expect_inertials_match_xml(imp, read_text(shared_case("urdf-inertial-read/leg_full.urdf")));
  const AnyModel<double> model(imp.model);
  Data<AnyModel<double>> data(model);
  // swing.csv: one state, columns q_, qd_, qdd_ per joint by name
  std::istringstream csv(read_text(shared_case("urdf-inertial-read/swing.csv")));
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  std::map<std::string, double> value;
  std::istringstream h(header), r(row);
  for (std::string name, v; std::getline(h, name, ',') && std::getline(r, v, ',');) value[name] = std::stod(v);
  const int n = model.size();
  Eigen::VectorXd q(n), qd(n), qdd(n);
  for (int i = 0; i < n; ++i) {
    const std::string& name = imp.model.joints[std::size_t(i)].name;
    q[i] = value.at("q_" + name);
    qd[i] = value.at("qd_" + name);
    qdd[i] = value.at("qdd_" + name);
  }
  rnea<Terms::Full>(model, data, q, qd, qdd);
  ASSERT_EQ(imp.model.joints[0].name, "hip_flexion");
  const double expected = 10 * (0.12 + 8.5 * 0.18 * 0.18 + 0.045 + 3.5 * 0.59 * 0.59);  // 16.5875 N m
  EXPECT_NEAR(data.tau[0], expected, 1e-12 * expected);
  EXPECT_NEAR(data.tau[0], 16.5875, 1e-12);
}

TEST(UrdfCases, UnreadableInertialsNameFileLineAndLink) {
  REQUIRE_FILE(shared_case("urdf-inertial-read/leg_principal_only.urdf"));
  expect_all(import_error(shared_case("urdf-inertial-read/leg_principal_only.urdf")),
             {"leg_principal_only.urdf:8: link 'thigh'", "<inertia> lacks ixy, ixz, iyz"});
  expect_all(import_error(shared_case("urdf-inertial-read/w_mass_as_text.urdf")),
             {"w_mass_as_text.urdf:4: link 'a'", "<mass> has no value attribute", "'2.5'"});
  expect_all(import_error(shared_case("urdf-inertial-read/w_no_mass_element.urdf")),
             {"w_no_mass_element.urdf:4: link 'a'", "<inertial> has no <mass"});
  // the same body written correctly
  const std::string ref = shared_case("urdf-inertial-read/reference.urdf");
  const auto imp = hu::import_urdf_file(ref);
  expect_inertials_match_xml(imp, read_text(ref));
  EXPECT_DOUBLE_EQ(imp.model.joints.at(0).body.mass, 2.5);
}

TEST(UrdfErrors, EveryInertialGapIsAnError) {
  const auto link = [](const std::string& inertial) {
    return "<robot name=\"r\">\n<link name=\"a\">" + inertial + "</link>\n</robot>\n";
  };
  expect_error(link(R"(<inertial><mass value="1"/></inertial>)"),
               {"bad.urdf:2: link 'a'", "<inertial> has no <inertia"});
  expect_error(link(R"(<inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" izz="1"/></inertial>)"),
               {"bad.urdf:2: link 'a'", "lacks iyz"});
  expect_error(link(R"(<inertial><mass/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>)"),
               {"bad.urdf:2: link 'a'", "<mass> has no value attribute"});
  expect_error(
      link(R"(<inertial><mass value="1 kg"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>)"),
      {"bad.urdf:2: link 'a'", "'kg' is not a number"});
  expect_error(
      link(
          R"(<inertial><origin xyz="0 0"/><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>)"),
      {"bad.urdf:2: link 'a'", "expected 3 numbers, found 2"});
}

// urdfdom reads the first of two <inertial>, <mass>, <origin>, <axis>, ... and ignores the others
TEST(UrdfErrors, ASecondElementIsAnError) {
  const std::string inertia = R"(<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>)";
  const auto link = [&](const std::string& inside) {
    return "<robot name=\"r\">\n<link name=\"a\">\n" + inside + "\n</link>\n</robot>\n";
  };
  const std::string inertial = "<inertial><mass value=\"1\"/>" + inertia + "</inertial>";
  expect_error(link(inertial + "\n" + inertial),
               {"bad.urdf:4: link 'a'", "a second <inertial> in <link> (the first is on line 3)"});
  expect_error(link("<inertial><mass value=\"1\"/>\n<mass value=\"7\"/>" + inertia + "</inertial>"),
               {"bad.urdf:4: link 'a'", "a second <mass> in <inertial> (the first is on line 3)"});
  expect_error(
      link("<inertial><origin xyz=\"0 0 0\"/>\n<origin xyz=\"0 0 1\"/><mass value=\"1\"/>" + inertia + "</inertial>"),
      {"bad.urdf:4: link 'a'", "a second <origin> in <inertial>"});
  expect_error(link("<inertial><mass value=\"1\"/>" + inertia + "\n" + inertia + "</inertial>"),
               {"bad.urdf:4: link 'a'", "a second <inertia> in <inertial>"});
  // in a joint, each on its own line after the first
  const auto joint = [](const std::string& second) {
    return "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n"
           "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><origin xyz=\"0 0 0\"/>"
           "<axis xyz=\"0 1 0\"/><limit effort=\"1\" velocity=\"1\"/><dynamics damping=\"0\"/>\n" +
           second + "</joint>\n</robot>\n";
  };
  EXPECT_EQ(hu::import_urdf(joint("")).model.joints.size(), 1u);
  for (const char* second :
       {R"(<origin xyz="0 0 1"/>)", R"(<axis xyz="1 0 0"/>)", R"(<parent link="b"/>)", R"(<child link="a"/>)",
        R"(<limit effort="2" velocity="2"/>)", R"(<dynamics damping="1"/>)"}) {
    SCOPED_TRACE(second);
    const std::string tag = std::string(second).substr(0, std::string(second).find(' ')) + ">";
    expect_error(joint(second),
                 {"bad.urdf:5: joint 'j'", ("a second " + tag + " in <joint>").c_str(), "(the first is on line 4)"});
  }
}

// Numbers as urdfdom reads them, joint types and each joint's parts: checked first, with their line
TEST(UrdfErrors, NumbersTypesAndLimitsNameTheirLine) {
  const std::string inertia = R"(<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>)";
  const auto mass = [&](const std::string& value) {
    return two_links(R"(<joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>)",
                     "<inertial><mass value=\"" + value + "\"/>" + inertia + "</inertial>");
  };
  expect_error(mass(" 2 "), {"bad.urdf:2: link 'a'", "<mass value=\"\u24202\u2420\">", "blanks around the number",
                             "write value=\"2\""});
  expect_error(mass("2 "), {"bad.urdf:2: link 'a'", "blanks around the number"});
  expect_error(mass("0x2"), {"bad.urdf:2: link 'a'", "'0x2' is not a number"});
  expect_error(mass("2."), {"no error"});
  expect_error(mass("+.5e1"), {"no error"});
  // a vector's numbers are separated by spaces, as urdfdom splits it
  expect_error(two_links(R"(<joint name="j" type="fixed"><parent link="a"/><child link="b"/>)"
                         "<origin xyz=\"0&#9;0 1\"/></joint>"),
               {"bad.urdf:4: joint 'j'", "xyz=\"0\\t0 1\"", "separated by spaces only"});
  expect_error(two_links(R"(<joint name="j" type="continuous"><parent link="a"/><child link="b"/>)"
                         "<origin xyz=\" 0  0 1 \"/></joint>"),
               {"no error"});

  const auto joint = [](const std::string& type, const std::string& inside) {
    return two_links("<joint name=\"j\" type=\"" + type +
                     "\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 1 0\"/>" + inside + "</joint>");
  };
  expect_error(joint("hinge", kLimit), {"bad.urdf:4: joint 'j'", "unknown joint type 'hinge'", "expected revolute"});
  expect_error(two_links(R"(<joint name="j"><parent link="a"/><child link="b"/></joint>)"),
               {"bad.urdf:4: joint 'j'", "no type attribute"});
  expect_error(joint("revolute", ""), {"bad.urdf:4: joint 'j'", "a revolute joint needs <limit"});
  expect_error(joint("prismatic", ""), {"bad.urdf:4: joint 'j'", "a prismatic joint needs <limit"});
  expect_error(joint("revolute", R"(<limit lower="-1" upper="1" velocity="1"/>)"),
               {"bad.urdf:4: joint 'j'", "<limit> has no effort attribute"});
  expect_error(joint("revolute", R"(<limit lower="-1" upper="one" effort="1" velocity="1"/>)"),
               {"bad.urdf:4: joint 'j'", "<limit upper=\"one\">", "'one' is not a number"});
  expect_error(joint("continuous", R"(<dynamics/>)"),
               {"bad.urdf:4: joint 'j'", "<dynamics> has neither damping nor friction"});
  expect_error(joint("continuous", R"(<dynamics damping="0x1"/>)"), {"bad.urdf:4: joint 'j'", "'0x1' is not a number"});
  expect_error(joint("continuous", R"(<mimic multiplier="2"/>)"), {"bad.urdf:4: joint 'j'", "<mimic> has no joint"});
  expect_error(joint("continuous", R"(<safety_controller k_position="1"/>)"),
               {"bad.urdf:4: joint 'j'", "<safety_controller> has no k_velocity"});
  expect_error(joint("continuous", R"(<calibration rising="a"/>)"), {"bad.urdf:4: joint 'j'", "'a' is not a number"});
  // what urdfdom accepts is accepted
  expect_error(joint("revolute", R"(<limit effort="1" velocity="1"/><dynamics friction="0.1"/>)"), {"no error"});
  expect_error(joint("continuous", R"(<safety_controller k_velocity="10" soft_lower_limit="-1"/>)"), {"no error"});
}

TEST(UrdfErrors, ASecondRootElementIsAnErrorNotADroppedRobot) {
  // a </robot> too early: what follows it (a second <robot> here) is no part of the document
  const std::string two = R"(<robot name="arm">
<link name="base"/><link name="l1"/>
<joint name="j1" type="continuous"><parent link="base"/><child link="l1"/></joint>
</robot>
<robot name="arm">
<link name="l2"/>
<joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/></joint>
</robot>
)";
  expect_error(two, {"bad.urdf:5: <robot> after the root element <robot> has ended (line 1)", "one root element"});
  expect_error(
      two_links(R"(<joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>)") + "<link/>",
      {"bad.urdf:6: <link> after the root element <robot>"});
}

TEST(UrdfAxes, AnAxisOfAnyNonzeroFiniteLengthIsItsDirection) {
  // components whose squares overflow or underflow a double: the same joint as the unit axis
  const auto arm = [](const std::string& axis) {
    return R"(<robot name="r">
<link name="base"/><link name="a"><inertial><origin xyz="0.5 0 0"/><mass value="2"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/></inertial></link>
<joint name="j" type="continuous"><parent link="base"/><child link="a"/><axis xyz=")" +
           axis + R"("/></joint>
</robot>)";
  };
  const auto unit = hu::import_urdf(arm("0 1 0"));
  for (const char* axis : {"0 1e300 0", "0 1e-170 0", "0 4.9e-324 0"}) {
    SCOPED_TRACE(axis);
    const auto imp = hu::import_urdf(arm(axis));
    expect_same_description(unit.model, imp.model);
  }
  expect_error(arm("0 0 0"), {"bad.urdf:3: joint 'j'", "zero axis"});
}

TEST(UrdfWarnings, JointDampingAndFrictionAreSaidToBeLeftOut) {
  const auto arm = [](const std::string& dynamics) {
    return R"(<robot name="r">
<link name="base"/><link name="a"><inertial><mass value="2"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/></inertial></link>
<joint name="j" type="continuous"><parent link="base"/><child link="a"/><axis xyz="0 1 0"/>)" +
           dynamics + R"(</joint>
</robot>)";
  };
  const auto imp = hu::import_urdf(arm(R"(<dynamics damping="50" friction="20"/>)"), {}, "pend.urdf");
  ASSERT_EQ(imp.warnings.size(), 1u);
  expect_all(imp.warnings[0], {"pend.urdf:3: joint 'j'", "damping=\"50\" friction=\"20\"", "is left out"});
  EXPECT_TRUE(hu::import_urdf(arm(R"(<dynamics damping="0"/>)")).warnings.empty());
  // a fixed joint's never act: nothing to say
  const std::string fixed = R"(<robot name="r">
<link name="base"/><link name="a"><inertial><mass value="2"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/></inertial></link>
<link name="b"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/></inertial></link>
<joint name="j" type="continuous"><parent link="base"/><child link="a"/><axis xyz="0 1 0"/></joint>
<joint name="f" type="fixed"><parent link="a"/><child link="b"/><dynamics damping="3"/></joint>
</robot>)";
  EXPECT_TRUE(hu::import_urdf(fixed).warnings.empty());
  EXPECT_TRUE(hu::import_urdf(arm("")).warnings.empty());
}

// Coordinates of an origin beyond 1e6 m are an input error, not a DH row the importer cannot rebuild
TEST(UrdfErrors, AnOriginOutOfRangeNamesItsJoint) {
  const auto chain = [](const std::string& xyz) {
    return R"(<robot name="r">
<link name="base"/><link name="a"/><link name="b"/>
<joint name="j1" type="continuous"><parent link="base"/><child link="a"/><axis xyz="0 1 0"/></joint>
<joint name="j2" type="continuous"><parent link="a"/><child link="b"/><origin xyz=")" +
           xyz + R"("/><axis xyz="0 1 0"/></joint>
</robot>)";
  };
  const std::string what = error_of(chain("1e300 0 0"));
  EXPECT_EQ(what.find("internal error"), std::string::npos) << what;
  for (const char* p :
       {"bad.urdf:4: joint 'j2'", "<origin xyz=\"1e300 0 0\">", "the coordinate 1e+300 m", "at most 1e+06 m"})
    EXPECT_NE(what.find(p), std::string::npos) << "'" << p << "' not in: " << what;
  expect_error(chain("0 -1000001 0"), {"bad.urdf:4: joint 'j2'", "-1000001 m is out of range"});
  expect_error(chain("1e6 0 -1e6"), {"no error"});
  expect_error(R"(<robot name="r">
<link name="a"><inertial><origin xyz="0 0 2e6"/><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
</robot>)",
               {"bad.urdf:2: link 'a'", "2e+06 m is out of range"});
}

// The document and its <robot> element as urdfdom reads them, and lines as an editor counts them
TEST(UrdfErrors, TheRobotElementAndTheDocumentNameTheirLine) {
  const std::string body =
      "<link name=\"a\"/>\n<link name=\"b\"/>\n<joint name=\"j\" type=\"continuous\">"
      "<parent link=\"a\"/><child link=\"b\"/></joint>\n</robot>\n";
  expect_error("<?xml version=\"1.0\"?>\n<robot>\n" + body, {"bad.urdf:2: <robot> has no name attribute"});
  for (const char* version : {"2.0", "1", "1.0.0", "x"}) {
    SCOPED_TRACE(version);
    expect_error("<robot name=\"r\" version=\"" + std::string(version) + "\">\n" + body,
                 {"bad.urdf:1: <robot version=", "URDF's version is 1.0"});
  }
  expect_error("<robot name=\"r\" version=\"1.0\">\n" + body, {"no error"});
  expect_error("<!DOCTYPE robot [<!ENTITY s \"1\">]>\n<robot name=\"r\">\n" + body,
               {"bad.urdf:1: a <!DOCTYPE> with declarations of its own"});
  expect_error("<?xml version=\"1.0\"?>\n\n<model name=\"x\"/>",
               {"bad.urdf:3: no <robot> element (the document is a <model>)"});
  expect_error("<robot name=\"r\">\n</robot>", {"bad.urdf:1: robot 'r' has no links"});
  // a lone CR ends a line too (XML's end-of-line rule), as CR LF does
  std::string fault =
      "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n<joint name=\"j\" "
      "type=\"continuous\"><parent link=\"a\"/><child link=\"c\"/></joint>\n</robot>\n";
  expect_error(fault, {"bad.urdf:4: joint 'j': child link 'c' is not defined"});
  for (const char* end : {"\r", "\r\n"}) {
    std::string other = fault;
    for (std::size_t i = 0; (i = other.find('\n', i)) != std::string::npos; i += std::strlen(end))
      other.replace(i, 1, end);
    expect_error(other, {"bad.urdf:4: joint 'j': child link 'c' is not defined"});
  }
  // link names show their invisible characters
  expect_error(two_links(R"(<joint name="j" type="continuous"><parent link="a)"
                         "\u200B\"/><child link=\"b\"/></joint>"),
               {"parent link 'a<U+200B>' is not defined"});
}

// An rpy angle beyond 1e6 rad is refused like a far origin: its rotation would be round-off
TEST(UrdfErrors, AnRpyAngleOutOfRangeNamesItsElement) {
  const std::string joint =
      R"(<joint name="j" type="continuous"><parent link="a"/><child link="b"/><origin rpy="0 0 RPY"/></joint>)";
  const auto with = [&](const std::string& rpy) {
    return two_links(std::string(joint).replace(joint.find("RPY"), 3, rpy));
  };
  expect_error(with("1e20"), {"bad.urdf:4: joint 'j'", "<origin rpy=\"0 0 1e20\">",
                              "the angle 1e+20 rad is out of range", "at most 1e+06 rad"});
  expect_error(with("-1000001"), {"bad.urdf:4: joint 'j'", "-1000001 rad is out of range"});
  expect_error(with("-1e6"), {"no error"});
  const std::string inertia = R"(<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>)";
  expect_error(two_links(R"(<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>)",
                         "<inertial><origin rpy=\"3e7 0 0\"/><mass value=\"1\"/>" + inertia + "</inertial>"),
               {"bad.urdf:2: link 'a'", "the angle 3e+07 rad is out of range"});
}

// urdfdom refuses a whole file for a fault in a <visual>, a <collision> or a <material>, naming no line:
// each is named here with its line, and what urdfdom reads is accepted
TEST(UrdfErrors, VisualCollisionAndMaterialFaultsNameTheirLine) {
  const auto link_with = [](const std::string& inside, const std::string& before = "") {
    return "<robot name=\"r\">\n" + before + "<link name=\"a\">\n" + inside + "\n</link>\n</robot>\n";
  };
  const auto visual = [&](const std::string& geometry, const std::string& more = "") {
    return link_with("<visual>\n<geometry>" + geometry + "</geometry>" + more + "</visual>");
  };
  expect_error(visual(R"(<box size="1 2 x"/>)"),
               {"bad.urdf:4: link 'a'", "<box size=\"1 2 x\">", "'x' is not a number"});
  expect_error(visual(R"(<box size="1 2"/>)"), {"bad.urdf:4: link 'a'", "expected 3 numbers, found 2"});
  expect_error(visual(R"(<sphere radius="1 2"/>)"), {"bad.urdf:4: link 'a'", "expected 1 number, found 2"});
  expect_error(visual(R"(<sphere radius="nan"/>)"), {"bad.urdf:4: link 'a'", "'nan' is not a finite number"});
  expect_error(visual(R"(<sphere radius="-1"/>)"), {"bad.urdf:4: link 'a'", "a negative size"});
  expect_error(visual(R"(<sphere/>)"), {"bad.urdf:4: link 'a'", "<sphere> has no radius attribute"});
  expect_error(visual(R"(<cylinder radius="0.1"/>)"), {"bad.urdf:4: link 'a'", "<cylinder> has no length attribute"});
  expect_error(visual(R"(<mesh scale="1 1 1"/>)"), {"bad.urdf:4: link 'a'", "<mesh> has no filename attribute"});
  expect_error(visual(R"(<mesh filename="a.stl" scale="2 2"/>)"), {"bad.urdf:4: link 'a'", "expected 3 numbers"});
  expect_error(visual(R"(<capsule radius="1" length="2"/>)"),
               {"bad.urdf:4: link 'a'", "unknown shape <capsule>", "box, cylinder, sphere or mesh"});
  expect_error(visual(R"(<capsule radius="1" length="2"/><box size="1 1 1"/>)"), {"unknown shape <capsule>"});
  expect_error(visual(""), {"bad.urdf:4: link 'a'", "<geometry> holds no shape"});
  expect_error(visual("<sphere radius=\"1\"/>\n<box size=\"1 1 1\"/>"),
               {"bad.urdf:5: link 'a'", "a second shape <box> in <geometry> (the first, <sphere>, is on line 4)"});
  expect_error(link_with(R"(<collision><origin xyz="0 0 q"/><geometry><sphere radius="1"/></geometry></collision>)"),
               {"bad.urdf:3: link 'a'", "<origin xyz=\"0 0 q\">", "'q' is not a number"});
  expect_error(link_with("<collision>\n<origin xyz=\"0 0 0\"/></collision>"),
               {"bad.urdf:3: link 'a'", "<collision> has no <geometry>"});
  // a material's color, in a visual or at the top of the file
  const std::string sphere = R"(<sphere radius="1"/>)";
  expect_error(visual(sphere, "<material name=\"m\">\n<color rgba=\"1 0 x 1\"/></material>"),
               {"bad.urdf:5: link 'a'", "<color rgba=\"1 0 x 1\">", "'x' is not a number"});
  expect_error(visual(sphere, R"(<material name="m"><color rgba="1 0 0"/></material>)"),
               {"bad.urdf:4: link 'a'", "expected 4 numbers, found 3"});
  expect_error(link_with("", "<material name=\"skin\"><color rgba=\"1 0 0 nan\"/></material>\n"),
               {"bad.urdf:2: material 'skin'", "'nan' is not a finite number"});
  expect_error(link_with("", "<material name=\"skin\"><color/></material>\n"),
               {"bad.urdf:2: material 'skin'", "defines neither a <color rgba=\"...\">"});
  // materials as urdfdom reads them: a name; rgba in [0, 1]; one the robot defines gives a color or a texture
  expect_error(visual(sphere, R"(<material><color rgba="1 0 0 1"/></material>)"),
               {"bad.urdf:4: link 'a'", "<material> has no name attribute"});
  expect_error(visual(sphere, R"(<material name="m"><color rgba="1 0 2 1"/></material>)"),
               {"bad.urdf:4: link 'a'", "<color rgba=\"1 0 2 1\">", "the component 2 is outside [0, 1]"});
  expect_error(link_with("", "<material><color rgba=\"1 0 0 1\"/></material>\n"),
               {"bad.urdf:2: <material> has no name attribute"});
  expect_error(link_with("", "<material name=\"m\"><texture/></material>\n"),
               {"bad.urdf:2: material 'm'", "defines neither a <color rgba=\"...\"> nor a <texture filename=\"...\">"});
  expect_error(link_with("",
                         "<material name=\"m\"><color rgba=\"1 0 0 1\"/></material>\n<material "
                         "name=\"m\"><color rgba=\"0 0 0 1\"/></material>\n"),
               {"bad.urdf:3: material 'm'", "the name is used twice (first on line 2)"});
  // a shape's name shows its invisible characters
  expect_error(visual("<box size=\"1 1 1\"/><sphere\u200B radius=\"1\"/>"), {"no revolute or continuous joint"});
  expect_error(visual("<box\u200B size=\"1 1 1\"/>"), {"unknown shape <box<U+200B>>"});

  // what urdfdom reads is accepted (far visuals, any number of visuals and collisions, a named material, a
  // visual's material that only names one, a collision's material, which urdfdom never reads, an element of
  // an extension after the shape, a texture beside a color without rgba): the file is read through to the
  // model, which has no joint here
  expect_error(
      link_with(
          "<visual><geometry><box size=\"1 1 1\"/><x:extra xmlns:x=\"x\"/></geometry><material name=\"m\"><color/>"
          "</material></visual>\n<collision><geometry><sphere radius=\"1\"/></geometry><material/><material "
          "name=\"y\"><color rgba=\"1\"/></material></collision>",
          "<material name=\"t\"><color/><texture filename=\"a.png\"/></material>\n"),
      {"bad.urdf: no revolute or continuous joint"});
  expect_error(link_with(R"(<visual><origin xyz="2e6 0 0" rpy="0 3e7 0"/><geometry><box size="1 0 2"/></geometry>
<material name="m"/></visual><visual><geometry><mesh filename="a.stl"/></geometry></visual>
<collision><geometry><cylinder radius="0.1" length="1"/></geometry></collision>
<collision><geometry><sphere radius="0"/></geometry></collision>)",
                         "<material name=\"m\"><color rgba=\"1 0 0 1\"/></material>\n"),
               {"bad.urdf: no revolute or continuous joint"});
}

TEST(UrdfErrors, NumbersInMessagesKeepTheirDigits) {
  // a finger-sized tensor: 2.5e-06 > 1e-06 + 1e-06, not 0.000002 > 0.000000 + 0.000001
  const std::string finger = R"(<robot name="r">
<link name="finger"><inertial><mass value="0.02"/><inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="2.5e-6"/></inertial></link>
</robot>)";
  const std::string what = error_of(finger);
  expect_all(what, {"bad.urdf:2: link 'finger'", "triangle inequality", "2.5e-06 > ", "balance_inertia"});
  EXPECT_EQ(what.find("0.000000"), std::string::npos) << what;
  EXPECT_EQ(exact_number(0.1), "0.1");
  EXPECT_EQ(exact_number(2.5e-6), "2.5e-06");
  EXPECT_EQ(std::stod(exact_number(1.0 / 3)), 1.0 / 3);
}

// ---------------------------------------------------------------------------------------------------
// --balance-inertia: MuJoCo's rule, all three principal moments replaced by their mean

TEST(UrdfBalanceInertia, ReplacesTheViolatingMomentsByTheirMean) {
  // the finger's tensor turned by rpy: balancing gives the isotropic mean whatever the frame
  const std::string xml = R"(<robot name="r">
<link name="hand"><inertial><mass value="0.4"/><inertia ixx="4e-4" ixy="0" ixz="0" iyy="3e-4" iyz="0" izz="2e-4"/></inertial></link>
<link name="finger"><inertial><origin xyz="0.01 0 0.02" rpy="0.3 -0.2 0.7"/><mass value="0.02"/><inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="2.5e-6"/></inertial></link>
<joint name="flex" type="continuous"><parent link="hand"/><child link="finger"/><origin xyz="0.08 0 0"/><axis xyz="0 1 0"/></joint>
</robot>)";
  hu::ImportOptions opt;
  EXPECT_THROW(hu::import_urdf(xml, opt), hu::Error);  // strict by default
  opt.balance_inertia = true;
  const auto imp = hu::import_urdf(xml, opt, "finger.urdf");
  ASSERT_EQ(imp.warnings.size(), 1u);
  expect_all(imp.warnings[0],
             {"finger.urdf:3: link 'finger'", "violate the triangle inequality", "balanced to their mean"});
  const auto& body = imp.model.joints.at(0).body;
  EXPECT_LE((body.inertia - 1.5e-6 * Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-20);
  EXPECT_DOUBLE_EQ(body.mass, 0.02);
  // the mass and the centre of mass are the authored ones; valid links are untouched
  const P X = imp.links[1].pose;
  EXPECT_LE((body.com - X * Vector3d(0.01, 0, 0.02)).norm(), 1e-15);
  EXPECT_LE((imp.model.base_body.inertia - Eigen::Vector3d(4e-4, 3e-4, 2e-4).asDiagonal().toDenseMatrix())
                .cwiseAbs()
                .maxCoeff(),
            1e-18);
  // a valid file gives no warning; a tensor that is not positive semidefinite stays an error
  EXPECT_TRUE(hu::import_urdf(tree_urdf({{"0 0 0.1", "0 0 0", "0 0 1", ""}}), opt).warnings.empty());
  expect_error(R"(<robot name="r">
<link name="a"><inertial><mass value="1"/><inertia ixx="-1" ixy="0" ixz="0" iyy="1" iyz="0" izz="3"/></inertial></link>
</robot>)",
               {"bad.urdf:2: link 'a'", "not positive semidefinite"}, opt);
}

// ---------------------------------------------------------------------------------------------------
// The joint map's grammar and the rule for names

std::string map_error(const std::string& text) {
  try {
    hu::parse_joint_map(text, "my.map");
  } catch (const hu::Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(UrdfJointMap, EqualsWithOrWithoutBlanksLocks) {
  for (const char* line : {"j2 = 0.5", "j2 =0.5", "j2= 0.5", "j2=0.5", "\tj2\t=\t0.5\t# locked", "j2 = +5e-1"}) {
    SCOPED_TRACE(line);
    const auto map = hu::parse_joint_map(std::string("j1\n") + line + "\n", "my.map");
    ASSERT_EQ(map.entries.size(), 2u);
    EXPECT_TRUE(map.entries[1].locked);
    EXPECT_EQ(map.entries[1].urdf_joint, "j2");
    EXPECT_DOUBLE_EQ(map.entries[1].value, 0.5);
    EXPECT_EQ(map.entries[1].line, 2);
  }
  const auto renamed = hu::parse_joint_map("\xEF\xBB\xBFj1 hip\r\n  # comment\r\nj2\r\n", "my.map");  // BOM, CRLF
  ASSERT_EQ(renamed.entries.size(), 2u);
  EXPECT_EQ(renamed.entries[0].urdf_joint, "j1");
  EXPECT_EQ(renamed.entries[0].model_name, "hip");
  EXPECT_EQ(renamed.entries[1].model_name, "j2");
  EXPECT_EQ(renamed.entries[1].line, 3);
  // old Mac OS line ends: a lone \r ends a line too
  const auto mac = hu::parse_joint_map("j1 hip\r  # comment\r\rj2 = 0.5\r", "my.map");
  ASSERT_EQ(mac.entries.size(), 2u);
  EXPECT_EQ(mac.entries[0].model_name, "hip");
  EXPECT_TRUE(mac.entries[1].locked);
  EXPECT_EQ(mac.entries[1].value, 0.5);
  EXPECT_EQ(mac.entries[1].line, 4);
}

TEST(UrdfJointMap, MalformedLinesNameLineAndColumn) {
  expect_all(map_error("j1\nj = abc\n"), {"my.map:2:5: 'abc' is not a number"});
  expect_all(map_error("j a b\n"), {"my.map:1:5: unexpected 'b' after the model name"});
  expect_all(map_error("j = 0.5 x\n"), {"my.map:1:9: unexpected 'x' after the value"});
  expect_all(map_error("= 0.5\n"), {"my.map:1:1: expected a URDF joint name"});
  expect_all(map_error("j =\n"), {"my.map:1:4: expected a number after '='"});
  expect_all(map_error("j a=0.5\n"), {"my.map:1:4: '=' after a second name"});
  // numbers read as the CSV and BVH readers read them: beyond a double or underflowing to 0 refused, a
  // subnormal kept as it is
  expect_all(map_error("j = 1e999\n"), {"my.map:1:5: '1e999' is out of the range of a double: too large"});
  expect_all(map_error("j = 1e-400\n"), {"my.map:1:5: '1e-400' is out of the range of a double: too small, it would "
                                         "read as 0"});
  expect_all(map_error("j = 0.0001e-330\n"), {"'0.0001e-330' is out of the range of a double: too small"});
  expect_all(map_error("j = 1000e306\n"), {"'1000e306' is out of the range of a double: too large"});
  EXPECT_EQ(hu::parse_joint_map("j = -1e-320\n", "my.map").entries.at(0).value, -1e-320);
  EXPECT_EQ(hu::parse_joint_map("j = +2.5\n", "my.map").entries.at(0).value, 2.5);
  expect_all(map_error("j = -1e300\n"), {"my.map:1:5: a lock value beyond 1e6 (rad or m) is refused"});
  EXPECT_EQ(hu::parse_joint_map("j = -1e6\n", "my.map").entries.at(0).value, -1e6);
  for (const char* bad : {"j = 0x10", "j = nan", "j = inf", "j = 1.5.2", "j = -", "j = 1e", "j = 0.5=1"})
    EXPECT_NE(map_error(bad).find("is not a number"), std::string::npos) << bad << ": " << map_error(bad);
  // names that no CSV header could carry, shown visibly
  expect_all(map_error("j a,b\n"), {"my.map:1:3: joint 'a,b': the name holds a comma"});
  expect_all(map_error("j a\"b\n"), {"my.map:1:3:", "double quote"});
  expect_all(map_error("j\x0b\n"), {"my.map:1:1: joint 'j<U+000B>'", "control character"});
  expect_all(map_error("j \xE2\x80\x8Bhip\n"), {"my.map:1:3: joint '<U+200B>hip'", "invisible character"});
  expect_all(map_error("j1\nj2 \xEF\xBB\xBFhip\n"),
             {"my.map:2:4: joint '<U+FEFF>hip'", "invisible character, <U+FEFF>"});
  // a carriage return is a line end (CRLF, or a lone one as old Mac OS wrote them), never part of a name
  const auto stray = hu::parse_joint_map("ok\nj\r\r\nk\n", "my.map");
  ASSERT_EQ(stray.entries.size(), 3u);
  EXPECT_EQ(stray.entries[1].urdf_joint, "j");
  EXPECT_EQ(stray.entries[2].line, 4);
}

TEST(UrdfCases, GluedEqualsLocksTheJoint) {
  REQUIRE_FILE(shared_case("jointmap-syntax/map_eq_glued.jointmap"));
  hu::ImportOptions opt;
  opt.joints = hu::read_joint_map(shared_case("jointmap-syntax/map_eq_glued.jointmap"));
  ASSERT_EQ(opt.joints->entries.size(), 2u);
  EXPECT_TRUE(opt.joints->entries[1].locked);
  EXPECT_EQ(opt.joints->entries[1].value, 0.5);
  const std::string file = shared_case("jointmap-syntax/plain.urdf");
  const auto imp = hu::import_urdf_file(file, opt);
  ASSERT_EQ(imp.model.joints.size(), 1u);
  EXPECT_EQ(imp.model.joints[0].name, "j1");
  expect_inertials_match_xml(imp, read_text(file));
  // b sits on a at j2's origin turned 0.5 rad about x: the URDF's own kinematics at j2 = 0.5
  const auto m = parse(read_text(file));
  EXPECT_LE(fk_error(imp, read_text(file), {{"j2", 0.5}}, 20, nullptr), 1e-12);
  const P a_to_b = imp.links[1].pose.inverse() * imp.links[2].pose;
  const P expected = joint_transform(*m->getJoint("j2"), 0.5);
  EXPECT_LE((a_to_b.R - expected.R).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LE((a_to_b.p - expected.p).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(UrdfNames, OneRuleForEveryJointName) {
  EXPECT_EQ(hu::name_fault("r_hip_pitch"), "");
  EXPECT_EQ(hu::name_fault("left hip"), "");               // a blank inside is a CSV header's
  EXPECT_EQ(hu::name_fault("genou_gauche_\xC3\xA9"), "");  // UTF-8
  EXPECT_NE(hu::name_fault(""), "");
  EXPECT_NE(hu::name_fault("a,b"), "");
  EXPECT_NE(hu::name_fault("a\"b"), "");
  EXPECT_NE(hu::name_fault(" hip"), "");
  EXPECT_NE(hu::name_fault("hip "), "");
  EXPECT_NE(hu::name_fault("hip\xC2\xA0"), "");  // a no-break space at the end
  EXPECT_NE(hu::name_fault("a\tb"), "");
  EXPECT_NE(hu::name_fault("\xEF\xBB\xBFhip"), "");
  EXPECT_NE(hu::name_fault("hip\xFF"), "");  // not UTF-8
  // (messages show names by the command line's rule, text/shown.hpp, tested with the CSV reader's)

  // in a URDF: refused as the file is read, naming the joint and the link it moves
  const auto joint_named = [](const std::string& name) {
    return two_links("<joint name=\"" + name +
                     "\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/></joint>");
  };
  expect_error(joint_named("hip "), {"bad.urdf:4: joint 'hip\u2420' (moving link 'b')", "ends with a blank"});
  expect_error(joint_named("a,b"), {"bad.urdf:4: joint 'a,b'", "comma", "no CSV column"});
  expect_error(joint_named("a&quot;b"), {"bad.urdf:4: joint 'a\"b'", "double quote"});
  expect_error(joint_named("a&#9;b"), {"bad.urdf:4: joint 'a\\tb'", "control character"});
  expect_error(joint_named("\xEF\xBB\xBFhip"), {"bad.urdf:4: joint '<U+FEFF>hip'", "invisible"});
  // a link's and the robot's names head no column, but are text: UTF-8 without control characters
  const auto link_named = [](const std::string& name) {
    return "<robot name=\"r\">\n<link name=\"" + name +
           "\"/>\n<link name=\"b\"/>\n<joint name=\"j\" type=\"continuous\"><parent link=\"" + name +
           "\"/><child link=\"b\"/></joint>\n</robot>\n";
  };
  expect_error(link_named("b\xFF"
                          "ase"),
               {"bad.urdf:2: link 'b<0xFF>ase'", "not UTF-8"});
  expect_error(link_named("ba\x1b"
                          "se"),
               {"bad.urdf:2: not XML: a control character, <U+001B>"});  // (the XML reader's rule)
  expect_error("<robot name=\"r\xE9\">\n<link name=\"a\"/>\n</robot>\n",
               {"bad.urdf:1: <robot name=\"r<0xE9>\">", "not UTF-8"});
  EXPECT_EQ(hu::import_urdf(link_named("left, &quot;upper&quot; arm"), {}, "good.urdf").model.base_link_name,
            "left, \"upper\" arm");
  EXPECT_EQ(hu::import_urdf(link_named("two&#10;lines"), {}, "good.urdf").model.base_link_name, "two\nlines");
  // a map built in code is held to the same rule at import, naming its line
  hu::ImportOptions opt;
  opt.joints = hu::JointMap{"code.map", {hu::JointMapEntry{"j", "knee ", false, 0, 7}}};
  expect_error(joint_named("j"), {"code.map:7: joint 'j'", "model name 'knee\u2420'", "ends with a blank"}, opt);
}

// The fuzzers' seed corpora, with the inputs that once crashed or hung the importer, replayed as the
// fuzz targets read them (tests/fuzz/fuzz_inputs.hpp): each must give a result or an Error.
TEST(UrdfErrors, FuzzRegressions) {
  const std::filesystem::path dir(HUMANDYN_FUZZ_TEST_DATA);
  int n = 0;
  for (const auto& [corpus, run] : {std::pair{"urdf", &humandyn::fuzz::import_urdf_input},
                                    std::pair{"joint_map", &humandyn::fuzz::parse_joint_map_input}}) {
    for (const auto& f : std::filesystem::directory_iterator(dir / corpus)) {
      SCOPED_TRACE(f.path().string());
      try {
        run(read_text(f.path().string()));
      } catch (const hu::Error&) {
      }
      ++n;
    }
  }
  EXPECT_GE(n, 8);
}

}  // namespace

}  // namespace test_urdf
