// The URDF importer against the URDF's own kinematics (urdfdom poses composed link by link) and KDL's
// inverse dynamics on the same file (kdl_parser's tree, or a KDL tree re-rooted here by hand), on
// third-party files, small URDFs for every relation of consecutive axes, a round trip through the
// exporter, a physics identity on a re-rooted reduced human, and bad input.
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/urdf.hpp"

#include <gtest/gtest.h>
#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>

#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

namespace {

using namespace humandyn;
namespace hu = humandyn::urdf;
using Eigen::Vector3d;
using P = Pose<double>;
using Q = std::map<std::string, double>;  // URDF joint angles by name

std::string shared_urdf(const std::string& name) { return std::string(HUMANDYN_SHARED_DATA) + "/urdf/" + name; }

#define REQUIRE_FILE(path)                                                                            \
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "third-party file " << (path) << " is absent"; \
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
  return KDL::Frame(KDL::Rotation(X.R(0, 0), X.R(0, 1), X.R(0, 2), X.R(1, 0), X.R(1, 1), X.R(1, 2), X.R(2, 0), X.R(2, 1),
                                  X.R(2, 2)),
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
      const bool moves = (j->type == ::urdf::Joint::REVOLUTE || j->type == ::urdf::Joint::CONTINUOUS) && lk == locked.end();
      const P O = joint_transform(*j, lk == locked.end() ? 0.0 : lk->second);
      const Vector3d axis = Vector3d(j->axis.x, j->axis.y, j->axis.z).normalized();
      KDL::Joint joint(j->name + "_fixed", KDL::Joint::Fixed);
      P tip;
      if (forward) {
        tip = O;
        if (moves) joint = KDL::Joint(j->name, kdl(O).p, kdl(O).M * KDL::Vector(axis.x(), axis.y(), axis.z()), KDL::Joint::RotAxis);
      } else {
        tip = O.inverse();
        if (moves) joint = KDL::Joint(j->name, KDL::Vector::Zero(), KDL::Vector(-axis.x(), -axis.y(), -axis.z()), KDL::Joint::RotAxis);
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

// Imports a third-party file, checks FK on 100 configurations and inverse dynamics on 1000 states
// against kdl_parser's tree (at the URDF root) or a hand-rooted KDL tree (elsewhere).
void check_file(const std::string& file, const std::string& root, const std::string& up) {
  const std::string xml = read_text(file);
  hu::ImportOptions opt;
  opt.root = root;
  opt.gravity = hu::gravity_for_up(up);
  const auto imp = hu::import_urdf(xml, opt, file);
  double rot = 0;
  EXPECT_LE(fk_error(imp, xml, {}, 100, &rot), 1e-12) << file << " at " << root;
  EXPECT_LE(rot, 1e-12) << file << " at " << root;
  const auto m = parse(xml);
  const KDL::Tree tree = root.empty() ? kdl_parser_tree(xml) : kdl_tree_at(*m, root);
  double scale = 0;
  const double err = id_error(imp, tree, {}, 1000, &scale);
  EXPECT_LE(err, 1e-9) << file << " at " << root << " (largest torque " << scale << " N m)";
  EXPECT_GT(scale, 1.0) << "the comparison must see real torques";
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

}  // namespace
