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
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace humandyn {

template <class S>
using Vec3 = Eigen::Matrix<S, 3, 1>;
template <class S>
using Mat3 = Eigen::Matrix<S, 3, 3>;

/// Thrown when a model is built from an invalid description. The message names the joint and link at
/// fault; where() and joint() say where it lies in the description, for a reader that points into its
/// own file (a model file's entry).
class ModelError : public std::runtime_error {
 public:
  /// Where in a ModelDescription the fault lies.
  enum class Where {
    Model,    ///< the model as a whole (its size) or none in particular
    Base,     ///< the base: its pose or its body
    Joint,    ///< one joint's entry: joint() is its index
    Gravity,  ///< the gravity vector
  };

  /// \param what   the message
  /// \param where  where the fault lies
  /// \param joint  for Where::Joint, the 0-based index of the joint's entry in ModelDescription::joints
  explicit ModelError(const std::string& what, Where where = Where::Model, int joint = -1)
      : std::runtime_error(what), where_(where), joint_(where == Where::Joint ? joint : -1) {}

  Where where() const noexcept { return where_; }
  /// The 0-based index of the joint's entry at fault, -1 unless where() is Where::Joint.
  int joint() const noexcept { return joint_; }

 private:
  Where where_;
  int joint_;
};

/// One standard DH row (Denavit and Hartenberg 1955): lengths in metres, angles in radians. theta is the
/// offset added to q.
template <class S>
struct DHParameters {
  S a = 0, alpha = 0, d = 0, theta = 0;
  template <class T>
  DHParameters<T> cast() const {
    return {T(a), T(alpha), T(d), T(theta)};
  }
};

/// A rigid transform: x_parent = R * x_child + p (p in m).
template <class S>
struct Pose {
  Mat3<S> R = Mat3<S>::Identity();
  Vec3<S> p = Vec3<S>::Zero();
  Pose operator*(const Pose& o) const { return {R * o.R, R * o.p + p}; }
  Vec3<S> operator*(const Vec3<S>& x) const { return R * x + p; }
  Pose inverse() const { return {R.transpose(), -(R.transpose() * p)}; }
  template <class T>
  Pose<T> cast() const {
    return {R.template cast<T>(), p.template cast<T>()};
  }
};

// The parallel-axis theorem: what a mass m whose centre sits at d from a point adds to the rotational
// inertia about that point, m (|d|^2 1 - d d^T) (Featherstone, RBDA eq. 2.63), written with the first
// moment h = m d so that it comes out exactly symmetric. The one place where inertias change points.
template <class S>
inline Mat3<S> parallel_axis(S m, const Vec3<S>& d) noexcept {
  const Vec3<S> h = m * d;
  Mat3<S> P;
  P(0, 0) = h.y() * d.y() + h.z() * d.z();
  P(1, 1) = h.x() * d.x() + h.z() * d.z();
  P(2, 2) = h.x() * d.x() + h.y() * d.y();
  P(0, 1) = P(1, 0) = -h.x() * d.y();
  P(0, 2) = P(2, 0) = -h.x() * d.z();
  P(1, 2) = P(2, 1) = -h.y() * d.z();
  return P;
}

// A rigid body's inertia in one frame: its mass (kg), its centre of mass (m) and its rotational inertia
// about the centre of mass (kg m^2), all in that frame's coordinates (Featherstone, RBDA §2.13). The one
// inertia type of the library: links, the base body, body segments, lumped bodies and point masses.
template <class S>
struct RigidBodyInertia {
  S mass = 0;
  Vec3<S> com = Vec3<S>::Zero();
  Mat3<S> inertia = Mat3<S>::Zero();  // about com

  /// A point mass.
  /// \param m  mass (kg)
  /// \param p  its position (m)
  static RigidBodyInertia point_mass(S m, const Vec3<S>& p) { return {m, p, Mat3<S>::Zero()}; }

  /// The rotational inertia about another point, same axes, by the parallel-axis theorem.
  /// \param point  the point (m), in this body's frame
  /// \return 3 x 3 symmetric (kg m^2)
  Mat3<S> inertia_about(const Vec3<S>& point) const { return inertia + parallel_axis(mass, Vec3<S>(com - point)); }

  /// The same body expressed in another frame (rotated and translated).
  /// \param X  this body's frame as seen from the other: x_other = X.R x + X.p
  /// \return com' = X com, I' = X.R I X.R^T (symmetrised against round-off)
  RigidBodyInertia expressed_in(const Pose<S>& X) const {
    const Mat3<S> I = X.R * inertia * X.R.transpose();
    return {mass, X * com, S(0.5) * (I + I.transpose())};
  }

  /// Adds another body, given in the same frame: the two as one rigid body, of the total mass, at their
  /// common centre of mass, with each rotational inertia moved there by the parallel-axis theorem. A
  /// massless sum keeps this body's centre of mass.
  RigidBodyInertia& operator+=(const RigidBodyInertia& o) {
    const S m = mass + o.mass;
    const Vec3<S> c = m > 0 ? Vec3<S>((mass * com + o.mass * o.com) / m) : com;
    inertia = inertia_about(c) + o.inertia_about(c);
    mass = m;
    com = c;
    return *this;
  }
  friend RigidBodyInertia operator+(RigidBodyInertia a, const RigidBodyInertia& b) { return a += b; }

  template <class T>
  RigidBodyInertia<T> cast() const {
    return {T(mass), com.template cast<T>(), inertia.template cast<T>()};
  }
};

/// One joint and the link it moves.
template <class S>
struct JointDescription {
  std::string name;       // joint name (names the CSV columns: q_<name>, tau_<name>, ...)
  std::string link_name;  // name of the link the joint moves
  int parent = -1;        // parent joint, -1 for the base; parents come before children
  bool mounted = false;   // whether `mount` applies
  Pose<S> mount;          // parent link frame -> this joint's DH base frame
  DHParameters<S> dh;
  RigidBodyInertia<S> body;  // in this link's frame
  template <class T>
  JointDescription<T> cast() const {
    return {name, link_name, parent, mounted, mount.template cast<T>(), dh.template cast<T>(), body.template cast<T>()};
  }
};

/// A whole model as plain data.
template <class S>
struct ModelDescription {
  std::string name;
  std::vector<JointDescription<S>> joints;
  std::string base_link_name = "base";
  RigidBodyInertia<S> base_body;              // the body fixed to the base (the stance foot), in the base frame
  Pose<S> base_pose;                          // the base frame in the world (z up, x forward, y left)
  Vec3<S> gravity = Vec3<S>(0, 0, S(-9.81));  // in the world
  template <class T>
  ModelDescription<T> cast() const {
    ModelDescription<T> out{name,
                            {},
                            base_link_name,
                            base_body.template cast<T>(),
                            base_pose.template cast<T>(),
                            gravity.template cast<T>()};
    for (const auto& j : joints) out.joints.push_back(j.template cast<T>());
    return out;
  }
};

// A number in the shortest form that reads back to the same double (for messages: a finger-sized
// tensor reads 2.5e-06, not 0.000002).
inline std::string exact_number(double x) {
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, x).ptr;
  return std::string(buf, end);
}

// The round-off allowed in the checks of an inertia tensor (symmetry, positive semidefiniteness,
// triangle inequality) of a body of mass m: 64 roundings of a double relative to the larger of the
// largest coefficient and m times a square metre (what a tensor carries that was moved by the
// parallel-axis theorem across a body's size, m d^2), and for a coarser scalar type 64 of its roundings
// relative to the body's own largest coefficient besides. So a float model accepts what a double one does,
// rounded, and no more: an absolute float tolerance (7.6e-6 kg m^2) had taken a finger's negative moment
// for round-off, and an absolute double one (1 kg m^2's rounding) a milligram body's tensor of 1e-15 kg m^2
// whatever its signs.
template <class S>
double inertia_tolerance(const Mat3<S>& inertia, double mass) {
  constexpr double eps = std::numeric_limits<double>::epsilon(), eps_S = double(std::numeric_limits<S>::epsilon());
  const double largest = double(inertia.cwiseAbs().maxCoeff());
  return 64 * eps * std::max(largest, mass * 1.0 /* m^2 */) + (eps_S > eps ? 64 * eps_S * largest : 0.0);
}

/// The largest sizes a description may hold: lengths (DH a and d, mount offsets, centres of mass, the base
/// pose's position) up to 1e7 m (above the 1e6 m per coordinate that the URDF importer and the motion
/// readers allow), masses up to 1e9 kg, inertia coefficients up to 1e21 kg m^2 and gravity up to 1e5 m/s^2;
/// DH angles (theta, alpha) up to 1e6 rad, as the URDF importer's, where a double still resolves a joint
/// angle added to theta to 1e-10 rad.
/// Far beyond any body, they keep every product the algorithms form (a whole chain's inertia about the base,
/// times a rate at StepLimits) within the range of a float, so that a typo or a wrong unit is an error naming
/// its link rather than torques that overflow.
inline constexpr double max_description_length = 1e7;    // m
inline constexpr double max_description_mass = 1e9;      // kg
inline constexpr double max_description_inertia = 1e21;  // kg m^2
inline constexpr double max_description_gravity = 1e5;   // m/s^2, 10 000 g
inline constexpr double max_description_angle = 1e6;     // rad

/// Checks that a body is physically valid: finite, mass >= 0, inertia symmetric positive semidefinite
/// with principal moments obeying the triangle inequality, no rotational inertia without mass, and
/// within the largest sizes above.
/// \param body   the body to check
/// \param who    names the link in the message
/// \param where  where the body lies in a description, and joint its entry's index (see ModelError)
/// \throws ModelError naming `who` and the fault
template <class S>
void check_inertia(const RigidBodyInertia<S>& body, const std::string& who,
                   ModelError::Where where = ModelError::Where::Model, int joint = -1) {
  const auto fail = [&](const std::string& what) { throw ModelError(who + ": " + what, where, joint); };
  if (!std::isfinite(double(body.mass))) fail("mass is not finite");
  if (body.mass < 0) fail("negative mass " + exact_number(double(body.mass)) + " kg");
  if (!body.com.allFinite()) fail("centre of mass is not finite");
  if (!body.inertia.allFinite()) fail("inertia is not finite");
  if (double(body.mass) > max_description_mass)
    fail("mass " + exact_number(double(body.mass)) + " kg is beyond " + exact_number(max_description_mass) + " kg");
  if (const double r = body.com.template cast<double>().stableNorm(); r > max_description_length)
    fail("centre of mass " + exact_number(r) + " m from the frame's origin is beyond " +
         exact_number(max_description_length) + " m");
  // (against the bound as S holds it: 1e21 is no float, and a description at the bound is one in float too)
  if (const double i = double(body.inertia.cwiseAbs().maxCoeff()); i > double(S(max_description_inertia)))
    fail("inertia coefficient " + exact_number(i) + " kg m^2 is beyond " + exact_number(max_description_inertia) +
         " kg m^2");
  const double tol = inertia_tolerance(body.inertia, double(body.mass));
  if (double((body.inertia - body.inertia.transpose()).cwiseAbs().maxCoeff()) > tol)
    fail("inertia tensor is not symmetric");
  const Eigen::Matrix3d I = body.inertia.template cast<double>();
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I, Eigen::EigenvaluesOnly).eigenvalues();
  if (ev.minCoeff() < -tol)
    fail("inertia tensor is not positive semidefinite (eigenvalue " + exact_number(ev.minCoeff()) + ")");
  if (ev(2) > ev(0) + ev(1) + tol)
    fail("principal moments violate the triangle inequality (" + exact_number(ev(2)) + " > " + exact_number(ev(0)) +
         " + " + exact_number(ev(1)) + ")");
  if (body.mass == 0 && ev.maxCoeff() > tol) fail("a massless link has rotational inertia");
}

// What the algorithms read about one joint, precomputed from its description.
template <class S>
struct JointConstants {
  int parent = -1;
  Twist twist = Twist::Zero;
  S ca = 1, sa = 0;                 // cos and sin of alpha
  S theta = 0;                      // DH offset added to q
  S a = 0, d = 0;                   // DH lengths
  Vec3<S> pstar = Vec3<S>::Zero();  // origin of this frame seen from the DH base frame, in this frame: (a, d sa, d ca)
  bool mounted = false;
  Mat3<S> mount_R = Mat3<S>::Identity();
  Vec3<S> mount_p = Vec3<S>::Zero();
  S mass = 0;
  Vec3<S> com = Vec3<S>::Zero();
  Mat3<S> inertia = Mat3<S>::Zero();  // about the centre of mass
  // the link's inertia about its own origin, for the algorithms that work there (crba, aba)
  Vec3<S> h = Vec3<S>::Zero();               // first moment of mass m com
  Mat3<S> inertia_origin = Mat3<S>::Zero();  // rotational inertia about the origin

  // the numbers above, in one list, for code that treats each alike (crowd.hpp puts them in lanes)
  template <class Self>
  static auto numbers(Self& j) noexcept {
    return std::tie(j.ca, j.sa, j.theta, j.a, j.d, j.pstar, j.mount_R, j.mount_p, j.mass, j.com, j.inertia, j.h,
                    j.inertia_origin);
  }
};

template <class T, int N>
using PerJoint = std::conditional_t<N == Eigen::Dynamic, std::vector<T>,
                                    std::array<T, std::size_t(N < 0 ? 0 : N)>>;  // clang instantiates both branches

/// A validated, immutable model with the shape `Shape` (SeedShape: known at compile time; DynamicShape:
/// any tree). One Model serves many Data workspaces and threads.
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

  /// Validates a description against the shape and physics and packs it for the algorithms.
  /// \param description  the model as plain data (lengths in m, angles in rad, masses in kg)
  /// \throws ModelError naming the joint and link at fault (parents, DH rows, mounts, inertias, shape),
  ///   or for a description without joints
  explicit Model(ModelDescription<Scalar> description) : desc_(std::move(description)) {
    const int n = int(desc_.joints.size());
    if constexpr (Shape::is_static) {
      if (n != nj)
        throw ModelError("model '" + desc_.name + "': " + std::to_string(n) + " joints, the shape needs " +
                         std::to_string(nj));
    } else {
      if (n == 0) throw ModelError("model '" + desc_.name + "': no joints (a model moves at least one)");
      joints_.resize(std::size_t(n));
    }
    using Where = ModelError::Where;
    if (!desc_.gravity.allFinite())
      throw ModelError("model '" + desc_.name + "': gravity is not finite", Where::Gravity);
    if (const double g = double(desc_.gravity.template cast<double>().stableNorm()); g > max_description_gravity)
      throw ModelError("model '" + desc_.name + "': gravity " + exact_number(g) + " m/s^2 is beyond " +
                           exact_number(max_description_gravity) + " m/s^2",
                       Where::Gravity);
    if (!desc_.base_pose.R.allFinite() || !desc_.base_pose.p.allFinite())
      throw ModelError("model '" + desc_.name + "': base pose is not finite", Where::Base);
    if (const double r = desc_.base_pose.p.template cast<double>().stableNorm(); r > max_description_length)
      throw ModelError("model '" + desc_.name + "': base pose's position " + exact_number(r) +
                           " m from the world's origin is beyond " + exact_number(max_description_length) + " m",
                       Where::Base);
    check_rotation(desc_.base_pose.R, "model '" + desc_.name + "': base pose", Where::Base);
    check_inertia(desc_.base_body, "base link '" + desc_.base_link_name + "'", Where::Base);
    for (int i = 0; i < n; ++i) {
      const auto& jd = desc_.joints[std::size_t(i)];
      const std::string who = "joint " + std::to_string(i + 1) + " '" + jd.name + "' (link '" + jd.link_name + "')";
      const auto fail = [&](const std::string& what) { throw ModelError(who + ": " + what, Where::Joint, i); };
      if (jd.parent < -1 || jd.parent >= i)
        fail("parent " + std::to_string(jd.parent) + " must name an earlier joint or -1");
      if (jd.name.empty()) fail("the joint has no name (joint_index and the columns q_<name>, ... need one)");
      for (int k = 0; k < i; ++k) {
        const auto& other = desc_.joints[std::size_t(k)];
        if (other.name == jd.name) fail("joint name used twice (also joint " + std::to_string(k + 1) + "'s)");
        if (!jd.link_name.empty() && other.link_name == jd.link_name)
          fail("link name used twice (also joint " + std::to_string(k + 1) + "'s)");
      }
      if (!jd.link_name.empty() && jd.link_name == desc_.base_link_name) fail("link name is the base link's");
      const auto& dh = jd.dh;
      if (!std::isfinite(double(dh.a)) || !std::isfinite(double(dh.alpha)) || !std::isfinite(double(dh.d)) ||
          !std::isfinite(double(dh.theta)))
        fail("DH parameters are not finite");
      for (const auto& [name, length] : {std::pair{"a", double(dh.a)}, std::pair{"d", double(dh.d)}})
        if (std::abs(length) > max_description_length)
          fail(std::string("DH length ") + name + " = " + exact_number(length) + " m is beyond " +
               exact_number(max_description_length) + " m");
      for (const auto& [name, angle] : {std::pair{"theta", double(dh.theta)}, std::pair{"alpha", double(dh.alpha)}})
        if (std::abs(angle) > max_description_angle)
          fail(std::string("DH angle ") + name + " = " + exact_number(angle) + " rad is beyond " +
               exact_number(max_description_angle) + " rad");
      if (jd.mounted) {
        if (!jd.mount.R.allFinite() || !jd.mount.p.allFinite()) fail("mount is not finite");
        if (const double r = jd.mount.p.template cast<double>().stableNorm(); r > max_description_length)
          fail("mount offset " + exact_number(r) + " m is beyond " + exact_number(max_description_length) + " m");
        check_rotation(jd.mount.R, who + ": mount", Where::Joint, i);
      }
      check_inertia(jd.body, who, Where::Joint, i);

      auto& c = joints_[std::size_t(i)];
      c.parent = jd.parent;
      c.twist = classify_twist(double(dh.alpha), twist_tolerance);
      using std::cos, std::sin;  // (or the scalar's own, found by its namespace)
      c.ca = cos(dh.alpha);
      c.sa = sin(dh.alpha);
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
      c.h = jd.body.mass * jd.body.com;
      c.inertia_origin = jd.body.inertia_about(Vec3<Scalar>::Zero());

      if constexpr (Shape::is_static) {
        const auto& s = Shape::spec;
        if (s.parent[std::size_t(i)] != jd.parent)
          fail("parent " + std::to_string(jd.parent + 1) + ", the shape needs " +
               std::to_string(s.parent[std::size_t(i)] + 1));
        if (s.twist[std::size_t(i)] != c.twist)
          fail("twist alpha = " + exact_number(double(dh.alpha)) + " rad does not match the shape's twist class");
        if (!s.mounted[std::size_t(i)] && jd.mounted) fail("the shape has no mount here");
        if (s.massless[std::size_t(i)] && jd.body.mass != 0) fail("the shape declares this link massless");
      }
    }
  }

  int size() const noexcept { return int(desc_.joints.size()); }
  const ModelDescription<Scalar>& description() const noexcept { return desc_; }
  const JointConstants<Scalar>& joint(int i) const noexcept { return joints_[std::size_t(i)]; }
  const Vec3<Scalar>& gravity() const noexcept { return desc_.gravity; }
  const Pose<Scalar>& base_pose() const noexcept { return desc_.base_pose; }
  const std::string& joint_name(int i) const noexcept { return desc_.joints[std::size_t(i)].name; }

  /// \return the index of the joint called `name`, -1 if none
  int joint_index(const std::string& name) const noexcept {
    for (int i = 0; i < size(); ++i)
      if (desc_.joints[std::size_t(i)].name == name) return i;
    return -1;
  }

  /// \return the total mass of the moving links and the base body (kg)
  Scalar total_mass() const noexcept {
    Scalar m = desc_.base_body.mass;
    for (const auto& j : desc_.joints) m += j.body.mass;
    return m;
  }

  /// \return the same model in another scalar type (validated again; may throw ModelError)
  template <class T>
  Model<T, Shape> cast() const {
    return Model<T, Shape>(desc_.template cast<T>());
  }

 private:
  static void check_rotation(const Mat3<Scalar>& R, const std::string& who, ModelError::Where where, int joint = -1) {
    const double tol = 1e3 * double(std::numeric_limits<Scalar>::epsilon());
    if (double((R.transpose() * R - Mat3<Scalar>::Identity()).cwiseAbs().maxCoeff()) > tol ||
        double(R.determinant()) < 0)
      throw ModelError(who + " rotation is not orthonormal and right-handed", where, joint);
  }

  ModelDescription<Scalar> desc_;
  PerJoint<JointConstants<Scalar>, nj> joints_{};
};

template <class S>
using HumanModel = Model<S, SeedShape>;
template <class S>
using AnyModel = Model<S, DynamicShape>;

}  // namespace humandyn
