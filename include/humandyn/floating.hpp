// The floating form of the human body: a free (6-DOF) base at the pelvis, the convention of
// biomechanics and of humanoid robotics, with both legs, the waist and the arms hanging from it as
// chains. It is the same body as the stance-rooted model: the stance leg re-hung from the pelvis as the
// mirror image of the swing leg, every link carrying the same rigid body; exact maps carry states and
// torques between the two forms.
//
// The base's velocity is a spatial vector in the base frame (Featherstone's order: angular; linear of
// the base origin), v_b; its acceleration a_b is the time derivative of those coordinates (what
// Pinocchio's free-flyer joint calls the local acceleration). Generalised velocities are (v_b, qd),
// 6 + nj of them; the mass matrix is (6 + nj) x (6 + nj) with the base block first.
//
//   const auto model = default_floating_model();            // FloatingHumanModel<double>
//   FloatingData<FloatingHumanModel<double>> fd(model);
//   floating_rnea(model, fd, X, v_b, a_b, q, qd, qdd);     // joint torques, and fd.base_wrench
//   floating_forward_dynamics(model, fd, X, v_b, q, qd, tau);  // fd.a_b, fd.data.qdd
//
// Featherstone, "Rigid Body Dynamics Algorithms" (2008), ch. 9 (floating bases: the base as a 6-DOF
// joint, the mass matrix's base block, forward dynamics through the Schur complement of the joints).
#pragma once

#include "humandyn/algorithm/aba.hpp"
#include "humandyn/algorithm/crba.hpp"
#include "humandyn/algorithm/energy.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/ground_reaction.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/algorithm/ldlt.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/integrators.hpp"
#include "humandyn/stance.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <array>
#include <cmath>

namespace humandyn {

namespace detail {

// The seed shape re-rooted at the pelvis. The stance leg is the first chain (base to pelvis); the
// pelvis is its last link; the swing leg is the chain that hangs from the pelvis as long as the stance
// leg. The floating shape puts the swing leg's mirror image in the stance leg's place, hanging from the
// base; every other joint keeps its index, and what hung from the pelvis hangs from the base.
struct SeedReRooting {
  static constexpr ChainSpec stance = SeedShape::chains[0];
  static constexpr int pelvis = stance.first + stance.length - 1;
  static constexpr ChainSpec swing = [] {
    for (const auto& c : SeedShape::chains)
      if (c.parent == pelvis && c.length == stance.length) return c;
    return ChainSpec{-1, 0, -1};
  }();
  static_assert(stance.first == 0 && stance.parent == -1, "the stance leg hangs from the base");
  static_assert(swing.first > pelvis, "a swing leg of the stance leg's length hangs from the pelvis");
};

}  // namespace detail

/// The shape of the floating form (16 joints): joints 0-3 the right leg from the hip down (the left
/// leg's mirror image), the others as in SeedShape, hanging from the base where they hung from the pelvis.
struct FloatingSeedShape {
  static constexpr int nj = SeedShape::nj;
  static constexpr bool is_static = true;
  static constexpr ShapeSpec<nj> spec = [] {
    using R = detail::SeedReRooting;
    ShapeSpec<nj> s = SeedShape::spec;
    for (int k = 0; k < R::stance.length; ++k) {
      const auto i = std::size_t(k), m = std::size_t(R::swing.first + k);
      s.parent[i] = k - 1;
      s.twist[i] = SeedShape::spec.twist[m];
      s.mounted[i] = SeedShape::spec.mounted[m];
      s.massless[i] = SeedShape::spec.massless[m];
    }
    for (int i = R::stance.length; i < nj; ++i)
      if (s.parent[std::size_t(i)] == R::pelvis) s.parent[std::size_t(i)] = -1;
    return s;
  }();
  static constexpr int num_chains = count_chains(spec.parent, nj);
  static constexpr std::array<ChainSpec, num_chains> chains = [] {
    std::array<ChainSpec, num_chains> out{};
    split_chains(spec.parent, nj, out);
    return out;
  }();
};
static_assert(FloatingSeedShape::num_chains == 5, "the floating body has five chains");

/// The floating form's model type: a model of FloatingSeedShape in the scalar type S.
template <class S>
using FloatingHumanModel = Model<S, FloatingSeedShape>;

/// The floating form of a stance-rooted seed body (right stance): base = the pelvis link, placed where
/// the pelvis stands at q = 0; the stance leg re-hung from the pelvis as the swing leg's mirror image
/// (named after the body table's mirror map)
/// (DH rows (a, alpha, d, theta) -> (-a, alpha, -d, theta), the first turned half a turn about its z
/// axis, theta + pi, which is the mirror's proper part at the pelvis); each of its links carries the
/// stance model's rigid body of the same name, re-expressed in its new frame. Throws ModelError if the
/// result does not describe the same body (checked by placing every link with both models).
inline ModelDescription<double> floating_description(const ModelDescription<double>& stance) {
  using R = detail::SeedReRooting;
  constexpr double pi = 3.14159265358979323846;
  const HumanModel<double> from(stance);
  Data<HumanModel<double>> df(from);
  forward_kinematics(from, df, HumanModel<double>::JointVector::Zero());

  ModelDescription<double> d = stance;
  d.name = stance.name + " (floating)";
  const auto& pelvis = stance.joints[std::size_t(R::pelvis)];
  d.base_link_name = pelvis.link_name;
  d.base_body = pelvis.body;
  d.base_pose = df.oMi[std::size_t(R::pelvis)];
  for (int k = 0; k < R::stance.length; ++k) {
    const auto& m = stance.joints[std::size_t(R::swing.first + k)];
    auto& j = d.joints[std::size_t(k)];
    j = m;
    // the names of the mirror images (body table): joint by joint, link by link (-1: the base link)
    const int mj = seed_body.mirror(R::swing.first + k), ml = seed_body.mirror_link(R::swing.first + k);
    j.name = stance.joints[std::size_t(mj)].name;
    j.link_name = ml >= 0 ? stance.joints[std::size_t(ml)].link_name : stance.base_link_name;
    j.parent = FloatingSeedShape::spec.parent[std::size_t(k)];
    j.dh.a = -m.dh.a;
    j.dh.d = -m.dh.d;
    if (k == 0) j.dh.theta += pi;
    j.body = RigidBodyInertia<double>{};
  }
  for (int i = R::stance.length; i < int(d.joints.size()); ++i)
    d.joints[std::size_t(i)].parent = FloatingSeedShape::spec.parent[std::size_t(i)];

  // the re-hung leg's bodies: the stance model's, moved into the new link frames (both at q = 0)
  const FloatingHumanModel<double> geometry(d);
  Data<FloatingHumanModel<double>> dg(geometry);
  forward_kinematics(geometry, dg, FloatingHumanModel<double>::JointVector::Zero());
  for (int k = 0; k < R::stance.length; ++k) {
    auto& j = d.joints[std::size_t(k)];
    const Pose<double>* old_frame = nullptr;
    const RigidBodyInertia<double>* body = nullptr;
    if (j.link_name == stance.base_link_name) {
      old_frame = &stance.base_pose;
      body = &stance.base_body;
    }
    for (int i = 0; i < R::stance.length; ++i)
      if (stance.joints[std::size_t(i)].link_name == j.link_name) {
        old_frame = &df.oMi[std::size_t(i)];
        body = &stance.joints[std::size_t(i)].body;
      }
    if (!body) throw ModelError("floating form: link '" + j.link_name + "' is not in model '" + stance.name + "'");
    const Pose<double> C = old_frame->inverse() * dg.oMi[std::size_t(k)];  // new frame seen from the old
    j.body.mass = body->mass;
    j.body.com = C.R.transpose() * (body->com - C.p);
    j.body.inertia = C.R.transpose() * body->inertia * C.R;
  }
  StanceSwitch<HumanModel<double>, FloatingHumanModel<double>>(from, FloatingHumanModel<double>(d));  // same body?
  return d;
}

/// The seed body of `p` in the floating form (floating_description of human_description(p)), validated, in
/// the scalar type S.
/// \throws ModelError as human_description and floating_description do
template <class S = double>
FloatingHumanModel<S> floating_model(const SeedParameters& p) {
  return FloatingHumanModel<S>(floating_description(human_description(p)).template cast<S>());
}

/// The embedded default body (de Leva's reference male) in the floating form.
template <class S = double>
FloatingHumanModel<S> default_floating_model() {
  return floating_model<S>(default_parameters());
}

/// The state of a floating body: base pose in the world, base velocity (angular; linear, base frame),
/// joint angles and rates.
template <class Model>
struct FloatingState {
  using S = typename Model::scalar_type;
  explicit FloatingState(const Model& model) : base(model.base_pose()) {
    q.setZero(model.size());
    qd.setZero(model.size());
  }
  Pose<S> base;
  SpatialVector<S> v_b = SpatialVector<S>::Zero();
  typename Model::JointVector q, qd;
};

/// Exact maps between the stance-rooted form and the floating form of one body. Built once (matches
/// the bodies by link name, allocates, throws ModelError when the two do not describe one body); the
/// maps are noexcept and allocation-free. A joint keeps its torque, angle rate and acceleration up to a
/// sign: the re-hung leg's joints turn the other way when parent and child swap.
template <class Stance, class Floating>
class FloatingMap {
  static constexpr int N = Stance::nj;
  using S = typename Stance::scalar_type;
  using JointVector = typename Floating::JointVector;

 public:
  FloatingMap(const Stance& stance, const Floating& floating) : switch_(stance, floating) {
    for (int i = 0; i < N; ++i)
      if (stance.description().joints[std::size_t(i)].link_name == floating.description().base_link_name) pelvis_ = i;
    if (pelvis_ < 0)
      throw ModelError("floating map: base link '" + floating.description().base_link_name + "' is not a link of '" +
                       stance.description().name + "'");
    // each floating joint's source and sign, read off the state map with one unit rate at a time
    StanceState<Floating> m;
    for (int j = 0; j < N; ++j) {
      switch_(stance, floating, Stance::JointVector::Zero(), Stance::JointVector::Unit(j), m);
      for (int k = 0; k < N; ++k)
        if (std::abs(std::abs(double(m.qd[k])) - 1) < 1e-6) {
          source_[std::size_t(k)] = j;
          sign_[std::size_t(k)] = m.qd[k] > 0 ? S(1) : S(-1);
        }
    }
    for (int k = 0; k < N; ++k)
      if (source_[std::size_t(k)] < 0)
        throw ModelError("floating map: joint '" + floating.description().joints[std::size_t(k)].name +
                         "' has no counterpart in '" + stance.description().name + "'");
    // the floating base frame in the stance model's pelvis link frame: one rigid body, so a constant pose
    // (the identity for the form the floating one was made from; a mirror image's differs)
    switch_(stance, floating, Stance::JointVector::Zero(), Stance::JointVector::Zero(), m);
    Data<Stance> ws(stance);
    forward_kinematics(stance, ws, Stance::JointVector::Zero());
    base_in_pelvis_ = ws.oMi[std::size_t(pelvis_)].inverse() * m.base_pose;
  }

  /// The floating state of the stance model's state (q, qd), its foot at rest in its base pose: the
  /// pelvis's pose and velocity, the joints' angles and rates. Uses `ws` for the velocity pass.
  template <class Q, class QD>
  void state(const Stance& stance, const Floating& floating, Data<Stance>& ws, const Eigen::MatrixBase<Q>& q,
             const Eigen::MatrixBase<QD>& qd, FloatingState<Floating>& out) const noexcept {
    StanceState<Floating> m;
    switch_(stance, floating, q, qd, m);
    out.base = m.base_pose;
    out.q = m.q;
    out.qd = m.qd;
    kinetic_energy(stance, ws, q, qd);  // link velocities, the pelvis's in its link frame
    out.v_b = to_base(ws.v[std::size_t(pelvis_)]);
  }

  /// The floating accelerations (a_b: angular; linear, base frame, and the joints') of the stance
  /// model's motion (q, qd, qdd), its foot at rest. Uses `ws` for a Newton–Euler pass and kinematics.
  template <class Q, class QD, class QDD>
  void acceleration(const Stance& stance, Data<Stance>& ws, const Eigen::MatrixBase<Q>& q,
                    const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<QDD>& qdd, SpatialVector<S>& a_b,
                    JointVector& qdd_floating) const noexcept {
    const auto k = std::size_t(pelvis_);
    rnea(stance, ws, q, qd, qdd);  // the pelvis's w, wd and vd = R^T (a - g), link frame
    kinetic_energy(stance, ws, q, qd);
    forward_kinematics(stance, ws, q);
    const Vec3<S> w = ws.v[k].template head<3>(), v = ws.v[k].template tail<3>();
    SpatialVector<S> a_pelvis;
    a_pelvis << ws.wd[k], ws.acc_origin[k] + ws.oMi[k].R.transpose() * stance.gravity() - w.cross(v);
    a_b = to_base(a_pelvis);
    for (int i = 0; i < N; ++i) qdd_floating[i] = sign_[std::size_t(i)] * S(qdd[source_[std::size_t(i)]]);
  }

  /// The floating form's joint torques from the stance form's (N m): joint k takes its source's, signed.
  template <class T>
  JointVector floating_torques(const Eigen::MatrixBase<T>& tau_stance) const noexcept {
    JointVector out;
    for (int k = 0; k < N; ++k) out[k] = sign_[std::size_t(k)] * S(tau_stance[source_[std::size_t(k)]]);
    return out;
  }

  /// The stance form's joint torques from the floating form's (N m).
  template <class T>
  typename Stance::JointVector stance_torques(const Eigen::MatrixBase<T>& tau_floating) const noexcept {
    typename Stance::JointVector out;
    for (int k = 0; k < N; ++k) out[source_[std::size_t(k)]] = sign_[std::size_t(k)] * S(tau_floating[k]);
    return out;
  }

  int source(int k) const noexcept { return source_[std::size_t(k)]; }  ///< the stance joint floating joint k is
  S sign(int k) const noexcept { return sign_[std::size_t(k)]; }        ///< +1, or -1 where it turns the other way
  int pelvis() const noexcept { return pelvis_; }                       ///< the stance joint whose link is the base
  /// The floating base frame in the stance model's pelvis link frame (constant).
  const Pose<S>& base_in_pelvis() const noexcept { return base_in_pelvis_; }

 private:
  // A velocity or acceleration of the pelvis (angular; linear, at the origin), from its link frame's
  // coordinates into the floating base frame's: a motion vector under the constant base_in_pelvis_.
  SpatialVector<S> to_base(const SpatialVector<S>& v) const noexcept {
    const Mat3<S>& R = base_in_pelvis_.R;
    SpatialVector<S> out;
    out << R.transpose() * v.template head<3>(),
        R.transpose() * (v.template tail<3>() + v.template head<3>().cross(base_in_pelvis_.p));
    return out;
  }

  StanceSwitch<Stance, Floating> switch_;
  std::array<int, N> source_ = [] {
    std::array<int, N> a{};
    a.fill(-1);
    return a;
  }();
  std::array<S, N> sign_{};
  int pelvis_ = -1;
  Pose<S> base_in_pelvis_;
};

/// The workspace of the floating-base algorithms: the joint algorithms' Data and the base's blocks.
template <class Model>
struct FloatingData {
  using S = typename Model::scalar_type;
  static constexpr int nj = Model::nj;
  using JointVector = typename Model::JointVector;

  explicit FloatingData(const Model& model)
      : data(model), base_body(detail::origin_form(model.description().base_body)) {
    Mbj.setZero(6, model.size());
    Y.setZero(model.size(), 6);
    DY.setZero(model.size(), 6);
    for (auto& v : step_q) v.setZero(model.size());
    for (auto& v : step_qd) v.setZero(model.size());
  }

  Data<Model> data;                  ///< the joints' workspace (data.M: the joint block; data.qdd)
  SpatialVector<S> base_wrench;      ///< from floating_rnea: wrench the base needs from outside (N m; N), base frame
  SpatialMatrix<S> Mbb;              ///< base block of the mass matrix: the whole body's spatial inertia at the base
  Eigen::Matrix<S, 6, nj> Mbj;       ///< base-joint block: column i = composite inertia of subtree i times S_i
  Eigen::Matrix<S, nj, 6> Y;         ///< L^-T M_bj^T, M_jj = L^T D L (forward dynamics)
  Eigen::Matrix<S, nj, 6> DY;        ///< D^-1 Y
  detail::BodyInertia<S> body;       ///< from floating_crba: the whole body about the base origin, base frame
  detail::BodyInertia<S> base_body;  ///< the base body alone, from the model
  SpatialVector<S> a_b;              ///< from floating_forward_dynamics: base acceleration (rad/s^2; m/s^2), base frame
  ArticulatedBase<S> base;           ///< the articulated-body algorithm's base (FdMethod::Articulated)
  // floating_step's angles and rates: the candidate state, and RK4's start, four stages and stage point
  std::array<JointVector, 7> step_q, step_qd;
};

namespace detail {

// The base's motion in the world from its pose and its velocity and acceleration coordinates (base
// frame): w = R w_b, wd = R wd_b, and the origin's acceleration R (dv_b/dt + w_b x v_b) (the
// velocity product dropped with the Coriolis terms).
template <Terms terms, class S>
inline BaseMotion<S> base_motion_of(const Pose<S>& X, const SpatialVector<S>& v_b,
                                    const SpatialVector<S>& a_b) noexcept {
  BaseMotion<S> m;
  m.pose = X;
  m.w = X.R * v_b.template head<3>();
  m.wd = X.R * a_b.template head<3>();
  Vec3<S> a = a_b.template tail<3>();
  if constexpr (terms == Terms::Full) a += v_b.template head<3>().cross(v_b.template tail<3>());
  m.a = X.R * a;
  return m;
}

}  // namespace detail

/// Floating-base inverse dynamics: the joint torques (N m, nj) and the base wrench (fd.base_wrench:
/// moment about the base origin; force, base frame) that produce the accelerations (a_b, qdd) at the
/// state (X, v_b, q, qd) under gravity and the external wrenches. For a free body moving as the laws of
/// motion allow, the base wrench is zero. Built on the moving-base Newton–Euler passes (rnea with a
/// BaseMotion) and the ground reaction (the base's wrench at the end of the inward pass).
/// \param X base pose in the world; \param v_b, a_b base velocity and acceleration (angular; linear), base frame.
template <Terms terms = Terms::Full, class Model, class Q, class QD, class QDD>
inline const typename Model::JointVector& floating_rnea(const Model& model, FloatingData<Model>& fd,
                                                        const Pose<typename Model::scalar_type>& X,
                                                        const SpatialVector<typename Model::scalar_type>& v_b,
                                                        const SpatialVector<typename Model::scalar_type>& a_b,
                                                        const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                                                        const Eigen::MatrixBase<QDD>& qdd,
                                                        const LinkWrenches<Model>* fext = nullptr) noexcept {
  const BaseMotion<typename Model::scalar_type> base = detail::base_motion_of<terms>(X, v_b, a_b);
  if (fext)
    rnea<terms>(model, fd.data, base, q, qd, qdd, *fext);
  else
    rnea<terms>(model, fd.data, base, q, qd, qdd);
  const auto r = ground_reaction<terms>(model, fd.data, base);
  fd.base_wrench << X.R.transpose() * r.moment, X.R.transpose() * r.force;
  return fd.data.tau;
}

/// The floating-base mass matrix's blocks at q: fd.Mbb (6 x 6, the whole body's spatial inertia at the
/// base origin, base frame; also as fd.body), fd.Mbj (6 x nj) and the joint block fd.data.M (crba). The
/// full matrix is [[Mbb, Mbj], [Mbj^T, M]] (kg m^2, kg m, kg). Needs nothing before it. Featherstone (2008)
/// sec. 9.2: the base is the root of the composite-rigid-body recursion, one pass in the link frames in
/// which each subtree's force F_i = Ic_i S_i, carried down its ancestors for M, goes on into the base frame.
template <class Model, class Q>
inline void floating_crba(const Model& model, FloatingData<Model>& fd, const Eigen::MatrixBase<Q>& q) noexcept {
  fd.body = fd.base_body;
  const detail::BaseRows<Model> rows{fd.body, fd.Mbj};
  detail::crba_impl<false, Terms::Full, false, true>(model, fd.data, q, q, nullptr, &rows);
  fd.Mbb = detail::spatial_inertia(fd.body.m, fd.body.h, fd.body.rotational());
}

namespace detail {

// Floating forward dynamics by the mass matrix, its blocks already computed at q (floating_crba).
template <Terms terms, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& floating_fd_given_mass_matrix(
    const Model& model, FloatingData<Model>& fd, const Pose<typename Model::scalar_type>& X,
    const SpatialVector<typename Model::scalar_type>& v_b, const Eigen::MatrixBase<Q>& q,
    const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<Tau>& tau, const LinkWrenches<Model>* fext) noexcept {
  using S = typename Model::scalar_type;
  using JointVector = typename Model::JointVector;
  auto& data = fd.data;
  // bias: what the base and the joints need for zero acceleration
  const SpatialVector<S> zero6 = SpatialVector<S>::Zero();
  floating_rnea<terms>(model, fd, X, v_b, zero6, q, qd, JointVector::Zero(model.size()), fext);
  const SpatialVector<S> f = -fd.base_wrench;
  auto& u = data.qdd;  // tau minus the bias, solved in place into the accelerations
  u = tau - data.tau;

  // with M = L^T D L, W = L^-T Mbj^T and y = L^-T u: the base's Schur complement Mbb - Mbj M^-1 Mbj^T is
  // Mbb - W^T D^-1 W, it gives a_b, and qdd = L^-1 D^-1 (y - W a_b)
  factorize_mass_matrix(model, data);
  fd.Y = fd.Mbj.transpose();
  detail::solve_lt(model, data, fd.Y);
  detail::solve_lt(model, data, u);
  fd.DY.noalias() = data.D.cwiseInverse().asDiagonal() * fd.Y;
  const SpatialMatrix<S> schur = fd.Mbb - fd.Y.transpose() * fd.DY;
  fd.a_b = schur.llt().solve(f - fd.DY.transpose() * u);
  u.noalias() -= fd.Y * fd.a_b;
  detail::solve_d(model, data, u);
  detail::solve_l(model, data, u);
  return data.qdd;
}

}  // namespace detail

/// Floating-base forward dynamics: the base acceleration fd.a_b (angular; linear, base frame) and the
/// joint accelerations fd.data.qdd (rad/s^2, returned) at the state (X, v_b, q, qd) under the joint
/// torques tau (N m), gravity and the external wrenches, with no wrench on the base.
/// FdMethod::MassMatrix: M (a_b, qdd) = (0, tau) - bias, the joint block factorised tree-sparse
/// (ldlt.hpp) and the base solved through its 6 x 6 Schur complement (Featherstone 2008, sec. 9.2).
/// FdMethod::Articulated: the articulated-body algorithm with the base as a free body (sec. 9.3).
template <FdMethod method = FdMethod::MassMatrix, Terms terms = Terms::Full, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& floating_forward_dynamics(
    const Model& model, FloatingData<Model>& fd, const Pose<typename Model::scalar_type>& X,
    const SpatialVector<typename Model::scalar_type>& v_b, const Eigen::MatrixBase<Q>& q,
    const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<Tau>& tau,
    const LinkWrenches<Model>* fext = nullptr) noexcept {
  auto& data = fd.data;
  if constexpr (method == FdMethod::Articulated) {
    fd.base.pose = X;
    fd.base.v = v_b;
    aba<terms>(model, data, fd.base, q, qd, tau, fext);
    fd.a_b = fd.base.a;
    return data.qdd;
  } else {
    floating_crba(model, fd, q);
    return detail::floating_fd_given_mass_matrix<terms>(model, fd, X, v_b, q, qd, tau, fext);
  }
}

namespace detail {

// Quaternion kinematics: the orientation's derivative for an angular velocity w in the body frame,
// dq/dt = q (0, w) / 2.
template <class S>
inline Eigen::Quaternion<S> quaternion_rate(const Eigen::Quaternion<S>& r, const Vec3<S>& w) noexcept {
  const Eigen::Quaternion<S> d = r * Eigen::Quaternion<S>(S(0), w.x(), w.y(), w.z());
  return Eigen::Quaternion<S>(S(0.5) * d.w(), S(0.5) * d.x(), S(0.5) * d.y(), S(0.5) * d.z());
}

}  // namespace detail

/// One step of length h (s) of a floating body under joint torques tau (N m), in place: Integrator::
/// SemiImplicitEuler (velocities first, then the pose by the exponential map of the new base velocity
/// and the angles) or Integrator::RungeKutta4 (the classical four stages on the orientation quaternion,
/// the base position in the world, the whole body's momentum in the world in place of v_b, the angles and
/// the joint rates; the quaternion renormalised at the end). RK4's momentum changes only by the gravity
/// wrench it integrates, so with no gravity it is kept to round-off at any h; v_b is recovered from it
/// through the mass matrix's base rows (Mbb v_b = h_b - Mbj qd). Hence RK4 takes Terms::Full only (a
/// compile-time error otherwise: without the velocity products the momentum is not the dynamics' own).
/// No Euler angles anywhere. Checked like `step` (integrators.hpp): bad input is refused before anything
/// is touched (a base orientation x.base.R that is not a rotation, R^T R = 1 within 1e-3 and det R > 0,
/// included), and a candidate state that is not finite or runs beyond `limits` (joint angles and rates;
/// the base's angular speed against max_abs_qd, its linear speed against max_base_speed) is not taken.
/// \return the status: ok, or the error with the quantity and the joint at fault (joint -1: the base);
///         the state is left untouched unless ok. No allocation, no exception.
template <Integrator integrator, FdMethod method = FdMethod::MassMatrix, Terms terms = Terms::Full, class Model,
          class Tau>
inline StepStatus floating_step(const Model& model, FloatingData<Model>& fd, FloatingState<Model>& x,
                                const Eigen::MatrixBase<Tau>& tau, typename Model::scalar_type h,
                                const StepLimits<typename Model::scalar_type>& limits = {}) noexcept {
  using S = typename Model::scalar_type;
  using JointVector = typename Model::JointVector;
  static_assert(integrator == Integrator::SemiImplicitEuler || integrator == Integrator::RungeKutta4,
                "floating_step: SemiImplicitEuler or RungeKutta4");
  static_assert(integrator != Integrator::RungeKutta4 || terms == Terms::Full,
                "floating_step: RungeKutta4 carries the body's momentum, which only the full dynamics (Terms::Full) "
                "change by gravity alone; take SemiImplicitEuler for other terms");
  // refuse bad input before touching anything (joint -1: the base)
  if (const StepStatus st = detail::check_time_step(h); !st.ok()) return st;
  if (int j = detail::first_non_finite(x.q); j >= 0) return {StepError::BadInput, Quantity::Angle, j};
  if (int j = detail::first_non_finite(x.qd); j >= 0) return {StepError::BadInput, Quantity::Velocity, j};
  if (int j = detail::first_non_finite(tau); j >= 0) return {StepError::BadInput, Quantity::Torque, j};
  if (!(x.base.R.allFinite() && x.base.p.allFinite())) return {StepError::BadInput, Quantity::Angle, -1};
  // the orientation a rotation: R^T R = 1 within 1e-3 (far beyond the drift of long runs, in float too)
  // and det R > 0
  if (!((x.base.R.transpose() * x.base.R - Mat3<S>::Identity()).cwiseAbs().maxCoeff() <= S(1e-3) &&
        x.base.R.determinant() > S(0)))
    return {StepError::BadInput, Quantity::Angle, -1};
  if (!x.v_b.allFinite()) return {StepError::BadInput, Quantity::Velocity, -1};
  // a candidate state passes when finite and within the limits
  const auto checked = [&](const auto& r, const Vec3<S>& p, const SpatialVector<S>& v, const JointVector& q,
                           const JointVector& qd) -> StepStatus {
    if (int j = detail::first_non_finite(q); j >= 0) return {StepError::NonFinite, Quantity::Angle, j};
    if (int j = detail::first_non_finite(qd); j >= 0) return {StepError::NonFinite, Quantity::Velocity, j};
    if (!(r.allFinite() && p.allFinite())) return {StepError::NonFinite, Quantity::Angle, -1};
    if (!v.allFinite()) return {StepError::NonFinite, Quantity::Velocity, -1};
    if (int j = detail::first_beyond(qd, limits.max_abs_qd); j >= 0) return {StepError::Runaway, Quantity::Velocity, j};
    if (!(v.template head<3>().norm() <= limits.max_abs_qd && v.template tail<3>().norm() <= limits.max_base_speed))
      return {StepError::Runaway, Quantity::Velocity, -1};
    if (int j = detail::first_beyond(q, limits.max_abs_q); j >= 0) return {StepError::Runaway, Quantity::Angle, j};
    return {};
  };
  if constexpr (integrator == Integrator::SemiImplicitEuler) {
    floating_forward_dynamics<method, terms>(model, fd, x.base, x.v_b, x.q, x.qd, tau);
    const SpatialVector<S> v = x.v_b + h * fd.a_b;
    JointVector& qd = fd.step_qd[0];
    qd = x.qd + h * fd.data.qdd;
    // pose: X' = X exp(h v), the SE(3) exponential of the body-frame twist
    const Vec3<S> phi = h * v.template head<3>(), rho = h * v.template tail<3>();
    const S angle = phi.norm();
    Mat3<S> dR = Mat3<S>::Identity(), V = Mat3<S>::Identity();
    if (angle > S(0)) {
      const Vec3<S> axis = phi / angle;
      dR = Eigen::AngleAxis<S>(angle, axis).toRotationMatrix();
      Mat3<S> K;
      K << S(0), -axis.z(), axis.y(), axis.z(), S(0), -axis.x(), -axis.y(), axis.x(), S(0);
      V += ((S(1) - std::cos(angle)) / angle) * K + ((angle - std::sin(angle)) / angle) * K * K;
    }
    Pose<S> X{x.base.R * dR, x.base.p + x.base.R * (V * rho)};
    JointVector& q = fd.step_q[0];
    q = x.q + h * qd;
    if (const StepStatus status = checked(X.R, X.p, v, q, qd); !status) return status;
    x.base = X;
    x.v_b = v;
    x.qd = qd;
    x.q = q;
  } else {
    // The state as (orientation quaternion, position, the whole body's momentum in the world, q, qd):
    // with the momentum h_w (angular about a fixed point; linear) in place of v_b, its rate is the gravity
    // wrench alone, so with no gravity every stage's rate is 0 and the step keeps the momentum to round-off
    // at any h. The fixed point is the base's position at the step's start, and positions are taken from
    // it: the step is then the same wherever the body is (taken about the world origin, far from it, the
    // moment of the linear momentum would swamp the angular one). Each stage recovers v_b from h_w through the
    // mass matrix's base rows, h_b = Mbb v_b + Mbj qd (base frame, about the base origin).
    struct Point {
      Eigen::Quaternion<S> r;
      Vec3<S> p;
      SpatialVector<S> h, v;  // h_w, and (derived) v_b
      JointVector &q, &qd;    // (in fd: sized once)
    };
    // v_b of a point from its momentum: the mass matrix's blocks at its angles, left in fd
    const auto velocity = [&](Point& s, const Mat3<S>& R) {
      floating_crba(model, fd, s.q);
      const Vec3<S> L = R.transpose() * s.h.template tail<3>();
      const Vec3<S> A = R.transpose() * (s.h.template head<3>() - s.p.cross(s.h.template tail<3>()));
      SpatialVector<S> h_b;
      h_b << A, L;
      s.v = fd.Mbb.llt().solve(h_b - fd.Mbj * s.qd);
    };
    const auto derivative = [&](Point& s, Point& d) {
      const Pose<S> X{s.r.normalized().toRotationMatrix(), s.p};
      velocity(s, X.R);
      // gravity's wrench about the fixed point at the centre of mass (the first moment floating_crba summed)
      const Vec3<S> c = X * Vec3<S>(fd.body.h / fd.body.m), weight = fd.body.m * model.gravity();
      d.h << c.cross(weight), weight;
      if constexpr (method == FdMethod::MassMatrix)
        detail::floating_fd_given_mass_matrix<terms>(model, fd, X, s.v, s.q, s.qd, tau, nullptr);
      else
        floating_forward_dynamics<method, terms>(model, fd, X, s.v, s.q, s.qd, tau);
      d.r = detail::quaternion_rate(s.r, Vec3<S>(s.v.template head<3>()));
      d.p = X.R * s.v.template tail<3>();
      d.q = s.qd;
      d.qd = fd.data.qdd;
    };
    const auto along = [](const Point& s, const Point& d, S t, Point& o) {
      o.r = Eigen::Quaternion<S>(s.r.coeffs() + t * d.r.coeffs());
      o.p = s.p + t * d.p;
      o.h = s.h + t * d.h;
      o.q = s.q + t * d.q;
      o.qd = s.qd + t * d.qd;
    };
    // the momentum at the start, from v_b
    floating_crba(model, fd, x.q);
    SpatialVector<S> h_w;
    {
      const SpatialVector<S> h_b = fd.Mbb * x.v_b + fd.Mbj * x.qd;
      const Vec3<S> L = x.base.R * h_b.template tail<3>();
      h_w << x.base.R * h_b.template head<3>(), L;  // about the base origin, the fixed point
    }
    const auto point = [&](int k) {
      return Point{Eigen::Quaternion<S>(x.base.R), Vec3<S>::Zero(),           h_w, x.v_b,
                   fd.step_q[std::size_t(k)],      fd.step_qd[std::size_t(k)]};
    };
    Point s0 = point(0), k1 = point(1), k2 = point(2), k3 = point(3), k4 = point(4), s = point(5), e = point(6);
    s0.q = x.q;
    s0.qd = x.qd;
    derivative(s0, k1);
    along(s0, k1, h / 2, s);
    derivative(s, k2);
    along(s0, k2, h / 2, s);
    derivative(s, k3);
    along(s0, k3, h, s);
    derivative(s, k4);
    e.r = Eigen::Quaternion<S>(s0.r.coeffs() +
                               (h / 6) * (k1.r.coeffs() + 2 * k2.r.coeffs() + 2 * k3.r.coeffs() + k4.r.coeffs()));
    e.p = (h / 6) * (k1.p + 2 * k2.p + 2 * k3.p + k4.p);  // from the fixed point
    e.h = s0.h + (h / 6) * (k1.h + 2 * k2.h + 2 * k3.h + k4.h);
    e.q = s0.q + (h / 6) * (k1.q + 2 * k2.q + 2 * k3.q + k4.q);
    e.qd = s0.qd + (h / 6) * (k1.qd + 2 * k2.qd + 2 * k3.qd + k4.qd);
    // v_b at the end, where the pose and the angles are finite (else the check below says which is not)
    const bool finite = e.r.coeffs().allFinite() && e.p.allFinite() && e.h.allFinite() && e.q.allFinite() &&
                        e.qd.allFinite() && e.r.norm() > S(0);
    const Mat3<S> R_end = finite ? Mat3<S>(e.r.normalized().toRotationMatrix()) : Mat3<S>::Identity();
    if (finite) velocity(e, R_end);
    e.p += x.base.p;  // back in the world
    if (!e.h.allFinite()) e.v.setConstant(std::numeric_limits<S>::quiet_NaN());
    if (const StepStatus status = checked(e.r.coeffs(), e.p, e.v, e.q, e.qd); !status) return status;
    if (!finite) return {StepError::NonFinite, Quantity::Angle, -1};
    x.base = Pose<S>{R_end, e.p};
    x.v_b = e.v;
    x.q = e.q;
    x.qd = e.qd;
  }
  return {};
}

}  // namespace humandyn
