// Stance switching. The seed roots the body at the stance foot; walking alternates feet. The
// left-stance model is the mirror image of the right-stance one (the seed body is left-right
// symmetric), on the same static shape: joint 1 is then the left ankle, 7-9 the right arm, 10-12 the
// left arm, 13-16 the right leg. StanceSwitch maps a state of one model to the state of the other
// that puts every link at the same place with the same velocity, and gives the new base pose, so a
// simulation can change the support foot at heel strike without a jump.
//
//   const auto right = human_model(p), left = left_stance_model(p);
//   const StanceSwitch to_left(right, left);
//   StanceState<HumanModel<double>> s;
//   to_left(right, left, q, qd, s);                 // noexcept, no allocation
//   const auto left_here = rebase(left, s.base_pose);  // the left-stance model standing where the foot is
#pragma once

#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/data.hpp"
#include "humandyn/detail/dh.hpp"
#include "humandyn/model.hpp"

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

namespace humandyn {

/// The name of a joint or link of `Body` in the body's mirror image: a joint's mirror partner (its
/// table's mirror column), and the link that touches the partners of the joints a link touches (the
/// right shank, between the right ankle and knee, is the left shank). Other names stay as they are.
template <const auto& Body = seed_body>
std::string mirror_name(const std::string& name) {
  if (const int j = Body.index(name); j >= 0) return Body.joints[std::size_t(Body.mirror(j))].name;
  if (name == Body.base_link) return Body.link_name(Body.mirror_link(-1));
  if (const int l = Body.link_index(name); l >= 0) return Body.link_name(Body.mirror_link(l));
  return name;
}

/// The mirror image of a world pose in the plane n . x = c (by default the x-z plane, y -> -y):
/// x_world -> M x_world + 2 c n with M = 1 - 2 n n^T. A mirrored frame is left-handed; turning it
/// through P = -1 makes it proper again: X' = M X P, i.e. R' = -M R, p' = M p + 2 c n.
/// \param X  a pose in the world (x_world = R x + p; m)
/// \param n  the plane's normal, a unit vector (world)
/// \param c  the plane's offset along n (m)
/// \return the mirrored pose, a proper rotation
template <class S>
Pose<S> mirror_pose(const Pose<S>& X, const Vec3<S>& n = Vec3<S>::UnitY(), S c = S(0)) {
  const Mat3<S> M = Mat3<S>::Identity() - S(2) * n * n.transpose();
  return {-(M * X.R), M * X.p + (S(2) * c) * n};
}

/// The mirror image of a body of `Body`'s parts, every name mapped by mirror_name. With every frame
/// mapped to M X P (mirror_pose), the transform between two frames becomes P T P: a DH row (a, alpha, d, theta)
/// becomes (-a, alpha, -d, theta) with the same joint angle, a mount (R, p) becomes (R, -p), and a body's
/// centre of mass c becomes -c, its inertia unchanged (P I P = I). Twist classes, parents, mounts and
/// massless links stay as they are: the mirror image runs on the same shape. Joint angles, rates and
/// torques of a mirrored motion are the same numbers (a moment is a pseudovector: n' = -M n in the world,
/// and the joint axis z' = -M z, so tau' = n'.z' = tau). The mirror is the plane n . x = c of the world
/// (as in mirror_pose; by default y = 0), gravity mirrored with the rest.
/// \param d  the description to mirror
/// \param n  the plane's normal, a unit vector (world)
/// \param c  the plane's offset along n (m)
/// \return the mirrored description, on the same shape
template <const auto& Body = seed_body>
ModelDescription<double> mirror_description(const ModelDescription<double>& d,
                                            const Eigen::Vector3d& n = Eigen::Vector3d::UnitY(), double c = 0) {
  const Eigen::Matrix3d M = Eigen::Matrix3d::Identity() - 2 * n * n.transpose();
  ModelDescription<double> out = d;
  out.base_link_name = mirror_name<Body>(d.base_link_name);
  out.base_pose = mirror_pose(d.base_pose, n, c);
  out.gravity = M * d.gravity;
  out.base_body.com = -d.base_body.com;
  for (auto& j : out.joints) {
    j.name = mirror_name<Body>(j.name);
    j.link_name = mirror_name<Body>(j.link_name);
    j.dh.a = -j.dh.a;
    j.dh.d = -j.dh.d;
    j.mount.p = -j.mount.p;
    j.body.com = -j.body.com;
  }
  return out;
}

/// The body standing on its other foot: the mirror image of a right-stance description (or of
/// human_description<Body>(p)) in the body's mid-plane, whose base is the other ankle, in the same world
/// (gravity as it was). The mid-plane is across the root joint's axis (the ankle's, z of the base frame,
/// to the body's left) half-way between the ankles at q = 0, wherever the base pose puts the body. For a
/// symmetric body this is the same person, and at q = 0 both models stand in the same pose.
/// \param right  any body of `Body`'s shape rooted at its right ankle (e.g. one read from a file)
/// \return the left-stance description, named after `right` with " (left stance)"
/// \throws ModelError if `right` has not `Body`'s shape
template <const auto& Body = seed_body>
ModelDescription<double> left_stance_description(const ModelDescription<double>& right) {
  using M = Model<double, BodyShape<Body>>;
  const M model(right);
  Data<M> data(model);
  forward_kinematics(model, data, M::JointVector::Zero());
  // the other ankle: the mirror of the root joint turns about the axis at its parent's frame origin
  constexpr int other_ankle_frame = Body.parent(Body.mirror(0));
  const Eigen::Vector3d n = right.base_pose.R.col(2);
  const Eigen::Vector3d mid = 0.5 * (right.base_pose.p + data.oMi[std::size_t(other_ankle_frame)].p);
  ModelDescription<double> d = mirror_description<Body>(right, n, n.dot(mid));
  d.gravity = right.gravity;
  d.name = right.name + " (left stance)";
  return d;
}

/// The left-stance description of the body of `p`: left_stance_description(human_description<Body>(p)).
/// \throws ModelError as human_description does (a length not positive and finite)
template <const auto& Body = seed_body>
ModelDescription<double> left_stance_description(const SeedParameters& p) {
  return left_stance_description<Body>(human_description<Body>(p));
}

/// The seed body of `p` standing on its left foot (left_stance_description), validated, in the scalar type S.
template <class S = double>
HumanModel<S> left_stance_model(const SeedParameters& p) {
  return HumanModel<S>(left_stance_description(p).template cast<S>());
}

/// The same model with its base frame placed at `base_pose` in the world (validated again; allocates:
/// a step done at a switch of support, not in the per-call loop).
/// \param base_pose  the base frame in the world (x_world = R x_base + p; m)
/// \throws ModelError if `base_pose` is not finite or its R not a rotation
template <class Model>
Model rebase(const Model& model, const Pose<typename Model::scalar_type>& base_pose) {
  auto d = model.description();
  d.base_pose = base_pose;
  return Model(std::move(d));
}

/// A state of a fixed-base model: where its base stands, the joint angles and rates.
template <class Model>
struct StanceState {
  Pose<typename Model::scalar_type> base_pose;  ///< the base frame in the world (p in m)
  typename Model::JointVector q;                ///< joint angles (rad), nj
  typename Model::JointVector qd;               ///< joint rates (rad/s), nj
};

/// Maps states of model `From` to states of model `To`, two trees of the same rigid bodies rooted at
/// different ones (matched by link name; the base counts as a body). Built once; the mapping itself is
/// noexcept and allocation-free. Both models need static shapes, the same number of joints and one
/// scalar type.
///
/// For every body b, its frame in To is a fixed offset from its frame in From: X_to(b) = X_from(b) C_b,
/// measured with both models at q = 0 (so both must stand in the same pose at q = 0). A switch then
///   1. places every body with From's forward kinematics: X_from(b), and its angular velocity w(b);
///   2. puts To's base on its body: base_pose = X_from(base) C_base;
///   3. walks To's joints outwards: with P the (mounted) parent frame, the DH rotation
///      Rz(theta + q) Rx(alpha) = P^T X_to(b) has first column (cos, sin, 0): q = atan2 - theta, in (-pi, pi];
///      the rate is the parent-to-child angular velocity along the joint axis: qd = (w(b) - w(parent)) . z.
/// Joint rates are relative quantities, so To's state always reproduces the motion relative to the new
/// base body; it equals the world motion when that body is still (the new stance foot at heel strike).
template <class From, class To>
class StanceSwitch {
  static_assert(From::shape_type::is_static && To::shape_type::is_static, "stance switching needs static shapes");
  static_assert(From::nj == To::nj, "both models must have the same joints");
  static_assert(std::is_same_v<typename From::scalar_type, typename To::scalar_type>, "one scalar type");
  static constexpr int N = From::nj;
  using S = typename From::scalar_type;

 public:
  /// Matches the bodies by name and measures the offsets C_b.
  /// \throws ModelError if a body of `to` is missing from `from`, or if `to` cannot follow `from` (the
  ///         models do not describe one body)
  StanceSwitch(const From& from, const To& to) {
    const auto body_name = [](const auto& model, int b) -> const std::string& {
      return b == 0 ? model.description().base_link_name : model.description().joints[std::size_t(b - 1)].link_name;
    };
    for (int b = 0; b <= N; ++b) {
      source_[std::size_t(b)] = -1;
      for (int a = 0; a <= N; ++a)
        if (body_name(from, a) == body_name(to, b)) source_[std::size_t(b)] = a;
      if (source_[std::size_t(b)] < 0)
        throw ModelError("stance switch: link '" + body_name(to, b) + "' of model '" + to.description().name +
                         "' is not in model '" + from.description().name + "'");
    }
    // offsets at q = 0
    const auto zero = From::JointVector::Zero();
    Data<From> df(from);
    Data<To> dt(to);
    forward_kinematics(from, df, zero);
    forward_kinematics(to, dt, To::JointVector::Zero());
    const auto pose = [](const auto& model, const auto& data, int b) {
      return b == 0 ? model.base_pose() : data.oMi[std::size_t(b - 1)];
    };
    for (int b = 0; b <= N; ++b)
      offset_[std::size_t(b)] = pose(from, df, source_[std::size_t(b)]).inverse() * pose(to, dt, b);

    // a pose away from home must be reachable by To's joints, or the two are not one body
    typename From::JointVector q, qd = From::JointVector::Zero();
    for (int i = 0; i < N; ++i) q[i] = S(0.5 * std::sin(1.7 * i + 0.3));
    StanceState<To> s;
    const S misfit = map(from, to, q, qd, s);
    const double tol = 1e4 * double(std::numeric_limits<S>::epsilon());
    if (!(double(misfit) <= tol))
      throw ModelError("stance switch: models '" + from.description().name + "' and '" + to.description().name +
                       "' do not describe the same body (a link misses its place by " + exact_number(double(misfit)) +
                       " m)");
  }

  /// The state of `to` for the state (q, qd) of `from` (the models this switch was built from; `to`'s own
  /// base pose is not read). Angles come out in (-pi, pi].
  /// \param q    `from`'s joint angles (rad), nj
  /// \param qd   `from`'s joint rates (rad/s), nj
  /// \param out  receives `to`'s base pose (world), angles (rad) and rates (rad/s)
  template <class Q, class QD>
  void operator()(const From& from, const To& to, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                  StanceState<To>& out) const noexcept {
    map(from, to, q, qd, out);
  }

  /// The body of `from` that carries `to`'s base (0: `from`'s base; k + 1: the link of joint k), and `to`'s
  /// base frame seen from that body's frame: in every state, `to`'s base pose is that body's pose times
  /// base_offset() (measured at q = 0).
  int base_body() const noexcept { return source_[0]; }
  const Pose<S>& base_offset() const noexcept { return offset_[0]; }

 private:
  // Fills `out`; returns how far (rotation entries plus metres) a placed frame lands from its target
  // (zero up to rounding when the models describe one body).
  template <class Q, class QD>
  S map(const From& from, const To& to, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
        StanceState<To>& out) const noexcept {
    constexpr S two_pi = S(6.283185307179586476925);
    // 1. every body of From in the world, and its angular velocity (body 0: the base, at rest)
    std::array<Pose<S>, N + 1> X;
    std::array<Vec3<S>, N + 1> w;
    X[0] = from.base_pose();
    w[0].setZero();
    for (int k = 0; k < N; ++k) {
      const auto& j = from.joint(k);
      Pose<S> P = X[std::size_t(j.parent + 1)];
      if (j.mounted) P = P * Pose<S>{j.mount_R, j.mount_p};
      S c, s;
      detail::cos_sin(S(j.theta + S(q[k])), c, s);
      X[std::size_t(k + 1)] = P * dh_pose(j, c, s);
      w[std::size_t(k + 1)] = w[std::size_t(j.parent + 1)] + P.R.col(2) * S(qd[k]);
    }
    // 2. To's base on its body
    out.base_pose = X[std::size_t(source_[0])] * offset_[0];
    // 3. To's joints, outwards
    std::array<Pose<S>, N + 1> Y;
    Y[0] = out.base_pose;
    S misfit = 0;
    for (int k = 0; k < N; ++k) {
      const auto& j = to.joint(k);
      const auto b = std::size_t(k + 1), parent = std::size_t(j.parent + 1);
      Pose<S> P = Y[parent];
      if (j.mounted) P = P * Pose<S>{j.mount_R, j.mount_p};
      const Pose<S> target = X[std::size_t(source_[b])] * offset_[b];
      const Mat3<S> R = P.R.transpose() * target.R;
      // in (-pi, pi]: remainder rounds a half turn to even, which can give -pi
      const double turn = std::remainder(std::atan2(R(1, 0), R(0, 0)) - j.theta, two_pi);
      const S qk = S(turn <= -0.5 * two_pi ? turn + two_pi : turn);
      out.q[k] = qk;
      S c, s;
      detail::cos_sin(S(j.theta + qk), c, s);
      Y[b] = P * dh_pose(j, c, s);
      out.qd[k] = (w[std::size_t(source_[b])] - w[std::size_t(source_[parent])]).dot(P.R.col(2));
      misfit = std::max(misfit, (Y[b].R - target.R).cwiseAbs().maxCoeff() + (Y[b].p - target.p).cwiseAbs().maxCoeff());
    }
    return misfit;
  }

  std::array<int, N + 1> source_{};      // To's body b (0: base, k + 1: link k) is From's body source_[b]
  std::array<Pose<S>, N + 1> offset_{};  // C_b: X_to(b) = X_from(source_[b]) * C_b
};

}  // namespace humandyn
