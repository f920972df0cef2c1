// The model: a tree of rigid links, each moved by one revolute joint and placed by a standard
// Denavit-Hartenberg row, T_i = Rz(theta_i + q_i) * Tz(d_i) * Tx(a_i) * Rx(alpha_i), optionally after a
// fixed mount transform from its parent link's frame. Joint i rotates about the z axis of its parent's
// (mounted) frame; link i's frame sits at the link's distal end.
//
// A ModelDescription is plain data (what builders, importers and printers exchange). A Model is a
// validated, immutable description packed for the algorithms; the buffers they write live in Data
// (data.hpp), so one Model serves many characters and threads.
#pragma once

#include "humandyn/body.hpp"
#include "humandyn/shape.hpp"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace humandyn {

template <class S> using Vec3 = Eigen::Matrix<S, 3, 1>;
template <class S> using Mat3 = Eigen::Matrix<S, 3, 3>;

// Thrown when a model is built from an invalid description; the message names the link at fault.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One standard DH row: lengths in metres, angles in radians. theta is the offset added to q.
template <class S>
struct DHParameters {
  S a = 0, alpha = 0, d = 0, theta = 0;
  template <class T> DHParameters<T> cast() const { return {T(a), T(alpha), T(d), T(theta)}; }
};

// Mass, centre of mass and rotational inertia about the centre of mass, in the link frame.
template <class S>
struct RigidBodyInertia {
  S mass = 0;
  Vec3<S> com = Vec3<S>::Zero();
  Mat3<S> inertia = Mat3<S>::Zero();
  template <class T> RigidBodyInertia<T> cast() const {
    return {T(mass), com.template cast<T>(), inertia.template cast<T>()};
  }
};

// A rigid transform: x_parent = R * x_child + p.
template <class S>
struct Pose {
  Mat3<S> R = Mat3<S>::Identity();
  Vec3<S> p = Vec3<S>::Zero();
  Pose operator*(const Pose& o) const { return {R * o.R, R * o.p + p}; }
  Vec3<S> operator*(const Vec3<S>& x) const { return R * x + p; }
  Pose inverse() const { return {R.transpose(), -(R.transpose() * p)}; }
  template <class T> Pose<T> cast() const { return {R.template cast<T>(), p.template cast<T>()}; }
};

// One joint and the link it moves.
template <class S>
struct JointDescription {
  std::string name;          // joint name (names the CSV columns: q_<name>, tau_<name>, ...)
  std::string link_name;     // name of the link the joint moves
  int parent = -1;           // parent joint, -1 for the base; parents come before children
  bool mounted = false;      // whether `mount` applies
  Pose<S> mount;             // parent link frame -> this joint's DH base frame
  DHParameters<S> dh;
  RigidBodyInertia<S> body;  // in this link's frame
  template <class T> JointDescription<T> cast() const {
    return {name, link_name, parent, mounted, mount.template cast<T>(), dh.template cast<T>(),
            body.template cast<T>()};
  }
};

// A whole model as plain data.
template <class S>
struct ModelDescription {
  std::string name;
  std::vector<JointDescription<S>> joints;
  std::string base_link_name = "base";
  RigidBodyInertia<S> base_body;  // the body fixed to the base (the stance foot), in the base frame
  Pose<S> base_pose;              // the base frame in the world (z up, x forward, y left)
  Vec3<S> gravity = Vec3<S>(0, 0, S(-9.81));  // in the world
  template <class T> ModelDescription<T> cast() const {
    ModelDescription<T> out{name, {}, base_link_name, base_body.template cast<T>(),
                            base_pose.template cast<T>(), gravity.template cast<T>()};
    for (const auto& j : joints) out.joints.push_back(j.template cast<T>());
    return out;
  }
};

// Throws ModelError unless `body` is physically valid; `who` names the link in the message.
template <class S>
void check_inertia(const RigidBodyInertia<S>& body, const std::string& who) {
  const auto fail = [&](const std::string& what) { throw ModelError(who + ": " + what); };
  if (!std::isfinite(double(body.mass))) fail("mass is not finite");
  if (body.mass < 0) fail("negative mass " + std::to_string(double(body.mass)) + " kg");
  if (!body.com.allFinite()) fail("centre of mass is not finite");
  if (!body.inertia.allFinite()) fail("inertia is not finite");
  const double scale = std::max(1.0, double(body.inertia.cwiseAbs().maxCoeff()));
  const double tol = 64 * double(std::numeric_limits<S>::epsilon()) * scale;
  if (double((body.inertia - body.inertia.transpose()).cwiseAbs().maxCoeff()) > tol)
    fail("inertia tensor is not symmetric");
  const Eigen::Matrix3d I = body.inertia.template cast<double>();
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I, Eigen::EigenvaluesOnly).eigenvalues();
  if (ev.minCoeff() < -tol) fail("inertia tensor is not positive semidefinite (eigenvalue " + std::to_string(ev.minCoeff()) + ")");
  if (ev(2) > ev(0) + ev(1) + tol)
    fail("principal moments violate the triangle inequality (" + std::to_string(ev(2)) + " > " +
         std::to_string(ev(0)) + " + " + std::to_string(ev(1)) + ")");
  if (body.mass == 0 && ev.maxCoeff() > tol) fail("a massless link has rotational inertia");
}

// What the algorithms read about one joint, precomputed from its description.
template <class S>
struct JointConstants {
  int parent = -1;
  Twist twist = Twist::Zero;
  S ca = 1, sa = 0;              // cos and sin of alpha
  S theta = 0;                   // DH offset added to q
  S a = 0, d = 0;                // DH lengths
  Vec3<S> pstar = Vec3<S>::Zero();  // origin of this frame seen from the DH base frame, in this frame: (a, d sa, d ca)
  bool mounted = false;
  Mat3<S> mount_R = Mat3<S>::Identity();
  Vec3<S> mount_p = Vec3<S>::Zero();
  S mass = 0;
  Vec3<S> com = Vec3<S>::Zero();
  Mat3<S> inertia = Mat3<S>::Zero();  // about the centre of mass
};

template <class T, int N>
using PerJoint = std::conditional_t<N == Eigen::Dynamic, std::vector<T>, std::array<T, (N < 0 ? 0 : N)>>;  // clang instantiates both branches

// A validated model with the shape `Shape` (SeedShape: known at compile time; DynamicShape: any tree).
template <class Scalar, class Shape = SeedShape>
class Model {
 public:
  using scalar_type = Scalar;
  using shape_type = Shape;
  static constexpr int nj = Shape::nj;
  using JointVector = Eigen::Matrix<Scalar, nj, 1>;
  // how close to 0, ±90° or 180° a DH twist must be to count as that special twist: 1e-12 rad, or a
  // few roundings of the scalar type if that is coarser (float)
  static constexpr double twist_tolerance = std::max(1e-12, 16 * double(std::numeric_limits<Scalar>::epsilon()));

  // Validates `description` against the shape and physics; throws ModelError naming the link at fault.
  explicit Model(ModelDescription<Scalar> description) : desc_(std::move(description)) {
    const int n = int(desc_.joints.size());
    if constexpr (Shape::is_static) {
      if (n != nj)
        throw ModelError("model '" + desc_.name + "': " + std::to_string(n) + " joints, the shape needs " +
                         std::to_string(nj));
    } else {
      joints_.resize(std::size_t(n));
    }
    if (!desc_.gravity.allFinite()) throw ModelError("model '" + desc_.name + "': gravity is not finite");
    if (!desc_.base_pose.R.allFinite() || !desc_.base_pose.p.allFinite())
      throw ModelError("model '" + desc_.name + "': base pose is not finite");
    check_rotation(desc_.base_pose.R, "model '" + desc_.name + "': base pose");
    check_inertia(desc_.base_body, "base link '" + desc_.base_link_name + "'");
    for (int i = 0; i < n; ++i) {
      const auto& jd = desc_.joints[std::size_t(i)];
      const std::string who = "joint " + std::to_string(i + 1) + " '" + jd.name + "' (link '" + jd.link_name + "')";
      if (jd.parent < -1 || jd.parent >= i)
        throw ModelError(who + ": parent " + std::to_string(jd.parent) + " must name an earlier joint or -1");
      for (int k = 0; k < i; ++k)
        if (desc_.joints[std::size_t(k)].name == jd.name) throw ModelError(who + ": joint name used twice");
      const auto& dh = jd.dh;
      if (!std::isfinite(double(dh.a)) || !std::isfinite(double(dh.alpha)) || !std::isfinite(double(dh.d)) ||
          !std::isfinite(double(dh.theta)))
        throw ModelError(who + ": DH parameters are not finite");
      if (jd.mounted) {
        if (!jd.mount.R.allFinite() || !jd.mount.p.allFinite()) throw ModelError(who + ": mount is not finite");
        check_rotation(jd.mount.R, who + ": mount");
      }
      check_inertia(jd.body, who);

      auto& c = joints_[std::size_t(i)];
      c.parent = jd.parent;
      c.twist = classify_twist(double(dh.alpha), twist_tolerance);
      c.ca = std::cos(dh.alpha);
      c.sa = std::sin(dh.alpha);
      // a special twist is taken as exact, so that every algorithm sees the same rotation
      if (c.twist != Twist::General) {
        c.ca = c.twist == Twist::Zero ? 1 : c.twist == Twist::Pi ? -1 : 0;
        c.sa = c.twist == Twist::HalfPi ? 1 : c.twist == Twist::MinusHalfPi ? -1 : 0;
      }
      c.theta = dh.theta;
      c.a = dh.a;
      c.d = dh.d;
      c.pstar = Vec3<Scalar>(dh.a, dh.d * c.sa, dh.d * c.ca);
      c.mounted = jd.mounted;
      c.mount_R = jd.mounted ? jd.mount.R : Mat3<Scalar>::Identity();
      c.mount_p = jd.mounted ? jd.mount.p : Vec3<Scalar>::Zero();
      c.mass = jd.body.mass;
      c.com = jd.body.com;
      c.inertia = jd.body.inertia;

      if constexpr (Shape::is_static) {
        const auto& s = Shape::spec;
        if (s.parent[std::size_t(i)] != jd.parent)
          throw ModelError(who + ": parent " + std::to_string(jd.parent + 1) + ", the shape needs " +
                           std::to_string(s.parent[std::size_t(i)] + 1));
        if (s.twist[std::size_t(i)] != c.twist)
          throw ModelError(who + ": twist alpha = " + std::to_string(double(dh.alpha)) +
                           " rad does not match the shape's twist class");
        if (!s.mounted[std::size_t(i)] && jd.mounted) throw ModelError(who + ": the shape has no mount here");
        if (s.massless[std::size_t(i)] && jd.body.mass != 0)
          throw ModelError(who + ": the shape declares this link massless");
      }
    }
  }

  int size() const noexcept { return int(desc_.joints.size()); }
  const ModelDescription<Scalar>& description() const noexcept { return desc_; }
  const JointConstants<Scalar>& joint(int i) const noexcept { return joints_[std::size_t(i)]; }
  const Vec3<Scalar>& gravity() const noexcept { return desc_.gravity; }
  const Pose<Scalar>& base_pose() const noexcept { return desc_.base_pose; }
  const std::string& joint_name(int i) const noexcept { return desc_.joints[std::size_t(i)].name; }

  // Index of the joint called `name`, -1 if none.
  int joint_index(const std::string& name) const noexcept {
    for (int i = 0; i < size(); ++i)
      if (desc_.joints[std::size_t(i)].name == name) return i;
    return -1;
  }

  // Total mass of the moving links and the base body.
  Scalar total_mass() const noexcept {
    Scalar m = desc_.base_body.mass;
    for (const auto& j : desc_.joints) m += j.body.mass;
    return m;
  }

  // The same model in another scalar type (validated again).
  template <class T>
  Model<T, Shape> cast() const { return Model<T, Shape>(desc_.template cast<T>()); }

 private:
  static void check_rotation(const Mat3<Scalar>& R, const std::string& who) {
    const double tol = 1e3 * double(std::numeric_limits<Scalar>::epsilon());
    if (double((R.transpose() * R - Mat3<Scalar>::Identity()).cwiseAbs().maxCoeff()) > tol ||
        double(R.determinant()) < 0)
      throw ModelError(who + " rotation is not orthonormal and right-handed");
  }

  ModelDescription<Scalar> desc_;
  PerJoint<JointConstants<Scalar>, nj> joints_{};
};

template <class S> using HumanModel = Model<S, SeedShape>;
template <class S> using AnyModel = Model<S, DynamicShape>;

}  // namespace humandyn
