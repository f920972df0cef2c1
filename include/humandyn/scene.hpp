// Scenes: leave out what a question does not need. A scene picks, when compiling,
//   - the dynamic terms (Terms::Full, NoCoriolis or GravityOnly; gravity itself on or off),
//   - the joints that move: the others are locked at angles given when the scene's model is built, and
//     the links they carry are merged into their parents' rigid bodies (lumped mass, parallel-axis
//     inertia), so what still moves feels exactly the same loads,
//   - the torques wanted: the backward pass runs only over the subtrees below the wanted joints, and the
//     forward pass only over those subtrees and their ancestors.
// A scene with everything in it is the full model. A locked scene runs on a smaller static shape
// (LockedShape), computed from the full shape by constexpr functions, so its loops unroll over fewer
// joints; output pruning removes whole steps at compile time, not with branches.
//
//   using S = scenes::UpperBody;                        // legs locked, pelvis fixed
//   auto model = S::model<double>(human_description(p), q_lock);
//   Data data(model);
//   scene_rnea<S>(model, data, S::reduce(q), S::reduce(qd), S::reduce(qdd));
#pragma once

#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/data.hpp"
#include "humandyn/detail/dh.hpp"
#include "humandyn/integrators.hpp"
#include "humandyn/model.hpp"
#include "humandyn/shape.hpp"

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <initializer_list>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace humandyn {

/// What a scene keeps, over the joints of the full shape (0-based). A structural type: it is the
/// template argument of Scene.
template <int N>
struct SceneSpec {
  Terms terms = Terms::Full;                ///< inertial, velocity-product and gravity terms (rnea.hpp)
  bool gravity = true;                      ///< false: the scene's model has no gravity (free fall, space)
  JointSet<N> locked{};                     ///< joints held at their lock angles; their links join the parent's body
  JointSet<N> wanted = JointSet<N>::all();  ///< torques asked for (locked joints have none); default: all
};

/// A joint set for SceneSpec: the listed joints (0-based) of an N-joint shape.
template <int N>
constexpr JointSet<N> joint_set(std::initializer_list<int> joints) {
  return JointSet<N>(joints);
}

namespace detail {

// How a tree shrinks when joints are locked (the same rules at compile time and at run time):
//   owner[l]:  the moving joint whose rigid body link l joins (l itself if it moves, -1: the base body);
//   reduced[i]: joint i's index in the smaller tree (-1 if locked), parents still before children;
//   base_link: the link the smaller model's base frame sits on: the deepest locked link above every
//              moving joint that has no moving ancestor (-1: the full model's base frame). Moving the base
//              there spares those joints a mount.
template <class IntArray>
struct TreeReduction {
  int nj = 0;
  IntArray reduced{};
  IntArray owner{};
  int base_link = -1;
};

template <class IntArray, class ParentArray, class LockedArray>
constexpr void reduce_tree(const ParentArray& parent, const LockedArray& locked, int n, TreeReduction<IntArray>& r) {
  r.nj = 0;
  for (int i = 0; i < n; ++i) r.reduced[std::size_t(i)] = locked[std::size_t(i)] ? -1 : r.nj++;
  for (int i = 0; i < n; ++i) {
    const int p = parent[std::size_t(i)];
    r.owner[std::size_t(i)] = !locked[std::size_t(i)] ? i : (p < 0 ? -1 : r.owner[std::size_t(p)]);
  }
  const auto ancestor_or_self = [&](int a, int l) {
    if (a < 0) return true;
    for (; l >= 0; l = parent[std::size_t(l)])
      if (l == a) return true;
    return false;
  };
  bool found = false;
  int base = -1;
  for (int i = 0; i < n; ++i) {
    const int p = parent[std::size_t(i)];
    const bool root_level = !locked[std::size_t(i)] && (p < 0 || r.owner[std::size_t(p)] < 0);
    if (!root_level) continue;
    if (!found) {
      base = p;
      found = true;
    } else {
      while (!ancestor_or_self(base, p)) base = parent[std::size_t(base)];
    }
  }
  r.base_link = base;
}

// The link joint i of the smaller tree hangs from, in full indices (-1: the full base), and whether
// locked joints now sit between them (then joint i needs a mount).
template <class IntArray, class ParentArray>
constexpr int attach_link(const ParentArray& parent, const TreeReduction<IntArray>& r, int i) {
  const int p = parent[std::size_t(i)];
  const int fp = p < 0 ? -1 : r.owner[std::size_t(p)];
  return fp < 0 ? r.base_link : fp;
}

template <int N>
constexpr TreeReduction<std::array<int, N>> reduce_shape(const ShapeSpec<N>& full, const JointSet<N>& locked) {
  TreeReduction<std::array<int, N>> r{};
  reduce_tree(full.parent, locked, N, r);
  return r;
}

// The smaller tree's ShapeSpec: parents renumbered, twists kept, a mount wherever locked joints were
// folded in, massless only if every link merged into it is massless.
template <int M, int N>
constexpr ShapeSpec<M> reduced_spec(const ShapeSpec<N>& full, const TreeReduction<std::array<int, N>>& r) {
  ShapeSpec<M> s{};
  for (int i = 0; i < N; ++i) {
    const int k = r.reduced[std::size_t(i)];
    if (k < 0) continue;
    const int p = full.parent[std::size_t(i)];
    const int fp = p < 0 ? -1 : r.owner[std::size_t(p)];
    s.parent[std::size_t(k)] = fp < 0 ? -1 : r.reduced[std::size_t(fp)];
    s.twist[std::size_t(k)] = full.twist[std::size_t(i)];
    s.mounted[std::size_t(k)] = full.mounted[std::size_t(i)] || p != attach_link(full.parent, r, i);
    bool massless = true;
    for (int l = 0; l < N; ++l)
      if (r.owner[std::size_t(l)] == i) massless = massless && full.massless[std::size_t(l)];
    s.massless[std::size_t(k)] = massless;
  }
  return s;
}

// The DH transform Rz(theta + q) Tz(d) Tx(a) Rx(alpha) of one row.
inline Pose<double> dh_transform(const DHParameters<double>& dh, double q) {
  double c, s, ca, sa;
  detail::cos_sin(dh.theta + q, c, s);  // exact at quarter turns, as the algorithms' own
  detail::cos_sin(dh.alpha, ca, sa);
  Pose<double> T;
  T.R << c, -s * ca, s * sa,  //
      s, c * ca, -c * sa,     //
      0, sa, ca;
  T.p = Eigen::Vector3d(dh.a * c, dh.a * s, dh.d);
  return T;
}

}  // namespace detail

/// Several rigid bodies (in one frame) as one (RigidBodyInertia's +): total mass, common centre of mass,
/// and the inertia about it by the parallel-axis theorem; all zero for massless parts only.
/// \param parts  bodies in one frame (kg; m; kg m^2 about each centre of mass)
/// \return the merged body, in the same frame
inline RigidBodyInertia<double> merge_inertias(const std::vector<RigidBodyInertia<double>>& parts) {
  RigidBodyInertia<double> out;
  for (const auto& b : parts) out += b;
  return out;
}

/// The description of `full` with the joints marked in `locked` held at q_lock: each locked joint's
/// mount and DH row at its lock angle become a fixed transform, folded into the mount of the first
/// moving joint below it; the links it carries join the body of the nearest moving joint above (or the
/// base body), their inertias merged by the parallel-axis theorem. The base frame moves to the deepest
/// locked link above every moving root joint (detail::reduce_tree).
/// \param full    the full body's description (nj joints)
/// \param locked  nj flags: the joints held still
/// \param q_lock  nj lock angles (rad); only the locked entries are read
/// \return the smaller description: the moving joints, in their order
/// \throws ModelError if `full` is not a valid body (named as the whole body's validation names it, so a
///         fault on a link the locks merge away is not hidden in the merged body), the sizes disagree, a
///         lock angle is not finite, or nothing moves
inline ModelDescription<double> lock_joints(const ModelDescription<double>& full, const std::vector<bool>& locked,
                                            const Eigen::VectorXd& q_lock) {
  (void)AnyModel<double>(full);
  const int n = int(full.joints.size());
  if (int(locked.size()) != n || int(q_lock.size()) != n)
    throw ModelError("model '" + full.name + "': locking needs one flag and one angle per joint (" + std::to_string(n) +
                     ")");
  std::vector<int> parent(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    parent[std::size_t(i)] = full.joints[std::size_t(i)].parent;
    if (locked[std::size_t(i)] && !std::isfinite(q_lock[i]))
      throw ModelError(
          "joint " + std::to_string(i + 1) + " '" + full.joints[std::size_t(i)].name + "': lock angle is not finite",
          ModelError::Where::Joint, i);
  }
  detail::TreeReduction<std::vector<int>> r;
  r.reduced.resize(static_cast<std::size_t>(n));
  r.owner.resize(std::size_t(n));
  detail::reduce_tree(parent, locked, n, r);
  if (r.nj == 0) throw ModelError("model '" + full.name + "': every joint is locked, nothing moves");

  // every link frame at the lock angles (moving joints at 0: no transform used below crosses one), in
  // the full model's base frame
  std::vector<Pose<double>> F(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const auto& j = full.joints[std::size_t(i)];
    Pose<double> P = j.parent < 0 ? Pose<double>{} : F[std::size_t(j.parent)];
    if (j.mounted) P = P * j.mount;
    F[std::size_t(i)] = P * detail::dh_transform(j.dh, locked[std::size_t(i)] ? q_lock[i] : 0.0);
  }
  const auto frame = [&](int l) { return l < 0 ? Pose<double>{} : F[std::size_t(l)]; };

  ModelDescription<double> out;
  out.name = full.name;
  out.gravity = full.gravity;
  const Pose<double> base = frame(r.base_link);
  out.base_pose = full.base_pose * base;
  out.base_link_name = r.base_link < 0 ? full.base_link_name : full.joints[std::size_t(r.base_link)].link_name;

  // the base body: the full base body and every locked link with no moving joint above it
  const Pose<double> base_inv = base.inverse();
  std::vector<RigidBodyInertia<double>> parts{full.base_body.expressed_in(base_inv)};
  for (int l = 0; l < n; ++l)
    if (r.owner[std::size_t(l)] < 0)
      parts.push_back(full.joints[std::size_t(l)].body.expressed_in(base_inv * F[std::size_t(l)]));
  out.base_body = merge_inertias(parts);

  for (int i = 0; i < n; ++i) {
    if (locked[std::size_t(i)]) continue;
    JointDescription<double> j = full.joints[std::size_t(i)];
    const int p = parent[std::size_t(i)];
    const int fp = p < 0 ? -1 : r.owner[std::size_t(p)];
    j.parent = fp < 0 ? -1 : r.reduced[std::size_t(fp)];
    // the locked joints between the link it now hangs from and its own DH base frame become its mount
    const int attach = detail::attach_link(parent, r, i);
    if (p != attach) {
      const Pose<double> own = j.mounted ? j.mount : Pose<double>{};
      j.mount = frame(attach).inverse() * frame(p) * own;
      j.mounted = true;
    }
    // its body: its own link and every locked link that now rides on it
    const Pose<double> Fi_inv = F[std::size_t(i)].inverse();
    parts.clear();
    for (int l = 0; l < n; ++l)
      if (r.owner[std::size_t(l)] == i)
        parts.push_back(full.joints[std::size_t(l)].body.expressed_in(Fi_inv * F[std::size_t(l)]));
    j.body = merge_inertias(parts);
    out.joints.push_back(std::move(j));
  }
  return out;
}

/// The shape of FullShape with the joints in Locked held still: fewer joints, computed when compiling.
template <class FullShape, JointSet<FullShape::nj> Locked>
struct LockedShape {
  using full_shape = FullShape;  ///< the shape before locking
  /// How the tree shrinks (detail::TreeReduction): each full joint's index here (-1: locked), each link's
  /// owner, the link the base frame moves to.
  static constexpr auto reduction = detail::reduce_shape<FullShape::nj>(FullShape::spec, Locked);
  static constexpr int nj = reduction.nj;  ///< number of moving joints
  static_assert(nj > 0, "a scene must leave at least one joint moving");
  static constexpr bool is_static = true;  ///< known when compiling: loops unroll
  /// Per-joint facts: parents renumbered, twists kept, a mount wherever locked joints were folded in.
  static constexpr ShapeSpec<nj> spec = detail::reduced_spec<nj, FullShape::nj>(FullShape::spec, reduction);
  static constexpr int num_chains = count_chains(spec.parent, nj);  ///< number of serial chains
  /// The serial chains (split_chains), in joint order.
  static constexpr std::array<ChainSpec, num_chains> chains = [] {
    std::array<ChainSpec, num_chains> out{};
    split_chains(spec.parent, nj, out);
    return out;
  }();
};

/// A scene over a static full shape. Its shape is the full shape when nothing is locked, else a
/// LockedShape; `requested`, `computed` and `reached` (over the scene's own joints) say which torques are
/// asked for, which joints run the whole Newton-Euler step (the subtrees of the requested ones) and which
/// only carry motion outwards (their ancestors).
template <class FullShape, SceneSpec<FullShape::nj> Spec>
struct BasicScene {
  static_assert(FullShape::is_static, "scenes are compile-time reductions of a static shape");
  static_assert(Spec.gravity || Spec.terms != Terms::GravityOnly,
                "a gravity-only scene without gravity computes nothing");

  using full_shape = FullShape;                           ///< the shape the scene reduces
  static constexpr SceneSpec<FullShape::nj> spec = Spec;  ///< what the scene keeps
  static constexpr Terms terms = Spec.terms;              ///< the dynamic terms of scene_rnea
  static constexpr int full_nj = FullShape::nj;           ///< number of joints of the full shape
  /// Whether any joint is locked (then the scene runs on a LockedShape).
  static constexpr bool any_locked = !Spec.locked.empty();
  /// The scene's shape: the full shape when nothing is locked, else LockedShape.
  using shape = std::conditional_t<any_locked, LockedShape<FullShape, Spec.locked>, FullShape>;
  static constexpr int nj = shape::nj;  ///< number of the scene's joints (the moving ones)
  /// The scene's model type, in scalar type S.
  template <class S>
  using model_type = Model<S, shape>;
  /// A joint vector of the full shape (full_nj entries).
  template <class S>
  using full_vector = Eigen::Matrix<S, full_nj, 1>;
  /// A joint vector of the scene (nj entries).
  template <class S>
  using vector = Eigen::Matrix<S, nj, 1>;

  /// Full joint index -> scene joint index (-1: locked).
  static constexpr std::array<int, full_nj> scene_index = [] {
    std::array<int, full_nj> out{};
    int k = 0;
    for (int i = 0; i < full_nj; ++i) out[std::size_t(i)] = Spec.locked[std::size_t(i)] ? -1 : k++;
    return out;
  }();
  /// Scene joint index -> full joint index.
  static constexpr std::array<int, nj> full_index = [] {
    std::array<int, nj> out{};
    for (int i = 0; i < full_nj; ++i)
      if (scene_index[std::size_t(i)] >= 0) out[std::size_t(scene_index[std::size_t(i)])] = i;
    return out;
  }();

  /// Per scene joint: its torque is asked for (SceneSpec::wanted).
  static constexpr std::array<bool, nj> requested = [] {
    std::array<bool, nj> out{};
    for (int k = 0; k < nj; ++k) out[std::size_t(k)] = Spec.wanted[std::size_t(full_index[std::size_t(k)])];
    return out;
  }();
  /// Per scene joint: runs the whole Newton-Euler step (requested, or below a requested joint): the
  /// torque at joint k needs the forces of its whole subtree.
  static constexpr std::array<bool, nj> computed = [] {
    std::array<bool, nj> out{};
    for (int k = 0; k < nj; ++k) {
      const int p = shape::spec.parent[std::size_t(k)];
      out[std::size_t(k)] = requested[std::size_t(k)] || (p >= 0 && out[std::size_t(p)]);
    }
    return out;
  }();
  /// Per scene joint: carries motion (computed, or above a computed joint): a computed joint needs the
  /// motion of every link above it.
  static constexpr std::array<bool, nj> reached = [] {
    std::array<bool, nj> out = computed;
    for (int k = nj - 1; k >= 0; --k) {
      const int p = shape::spec.parent[std::size_t(k)];
      if (out[std::size_t(k)] && p >= 0) out[std::size_t(p)] = true;
    }
    return out;
  }();
  /// Whether some joint is not computed (then scene_rnea skips steps rather than calling rnea).
  static constexpr bool prunes_outputs = [] {
    for (bool b : computed)
      if (!b) return true;
    return false;
  }();
  static_assert(
      [] {
        for (bool b : requested)
          if (b) return true;
        return false;
      }(),
      "a scene must ask for at least one torque");

  /// How many joints the forward pass visits (a measure of the code the scene compiles to).
  static constexpr int forward_steps = [] {
    int c = 0;
    for (bool b : reached) c += b ? 1 : 0;
    return c;
  }();
  /// How many joints the backward pass visits.
  static constexpr int backward_steps = [] {
    int c = 0;
    for (bool b : computed) c += b ? 1 : 0;
    return c;
  }();

  /// The scene's model of the body `full` (a description of the full shape), the locked joints held at
  /// q_lock. With SceneSpec::gravity false, the model's gravity is zero.
  /// \param full    description of the full shape (full_nj joints)
  /// \param q_lock  full_nj lock angles (rad), only the locked entries read; may be empty when nothing is locked
  /// \throws ModelError for an invalid body, lock angles of the wrong size, or a lock angle not finite
  template <class S = double>
  static model_type<S> model(const ModelDescription<double>& full, const Eigen::VectorXd& q_lock) {
    ModelDescription<double> d;
    if constexpr (any_locked) {
      const auto flags = Spec.locked.flags();
      d = lock_joints(full, std::vector<bool>(flags.begin(), flags.end()), q_lock);
    } else {
      if (q_lock.size() != full_nj && q_lock.size() != 0)
        throw ModelError("model '" + full.name + "': " + std::to_string(q_lock.size()) + " lock angles for " +
                         std::to_string(full_nj) + " joints");
      d = full;
    }
    if constexpr (!Spec.gravity) d.gravity.setZero();
    return model_type<S>(d.template cast<S>());
  }
  /// The scene's model when nothing is locked (no lock angles needed).
  template <class S = double>
  static model_type<S> model(const ModelDescription<double>& full) requires(!any_locked) {
    return model<S>(full, Eigen::VectorXd());
  }

  /// A full-size joint vector (angles, rates, accelerations) restricted to the scene's joints.
  /// \param full  full_nj entries
  /// \return nj entries, in the scene's joint order
  template <class V>
  static vector<typename V::Scalar> reduce(const Eigen::MatrixBase<V>& full) noexcept {
    vector<typename V::Scalar> out;
    for (int k = 0; k < nj; ++k) out[k] = full[full_index[std::size_t(k)]];
    return out;
  }
  /// Scene torques as a full-size vector: zero at locked joints and at joints not computed.
  /// \param scene  nj entries (N m)
  /// \return full_nj entries (N m)
  template <class V>
  static full_vector<typename V::Scalar> expand(const Eigen::MatrixBase<V>& scene) noexcept {
    full_vector<typename V::Scalar> out = full_vector<typename V::Scalar>::Zero();
    for (int k = 0; k < nj; ++k) out[full_index[std::size_t(k)]] = scene[k];
    return out;
  }
  /// Whether the full joint i's torque is among the scene's outputs (i 0-based, < full_nj).
  static constexpr bool outputs(int i) noexcept {
    return scene_index[std::size_t(i)] >= 0 && requested[std::size_t(scene_index[std::size_t(i)])];
  }

  /// Makes a full-model motion one the scene describes exactly: locked joints at their lock angles and
  /// still, no joint rates for NoCoriolis (its torques equal the full ones at qd = 0), no rates or
  /// accelerations for GravityOnly.
  /// \param q_lock       full_nj lock angles (rad), only the locked entries read
  /// \param q, qd, qdd   full_nj each (rad, rad/s, rad/s^2), changed in place
  template <class S>
  static void constrain(const Eigen::VectorXd& q_lock, full_vector<S>& q, full_vector<S>& qd,
                        full_vector<S>& qdd) noexcept {
    for (int i = 0; i < full_nj; ++i) {
      if (Spec.locked[std::size_t(i)]) {
        q[i] = S(q_lock[i]);
        qd[i] = 0;
        qdd[i] = 0;
      }
    }
    if constexpr (terms != Terms::Full) qd.setZero();
    if constexpr (terms == Terms::GravityOnly) qdd.setZero();
  }
};

/// A scene of the seed body (SeedShape).
template <SceneSpec<SeedShape::nj> Spec>
using Scene = BasicScene<SeedShape, Spec>;

/// Inverse dynamics in a scene: rnea with the scene's terms, on the scene's joints (vectors of size
/// Scene::nj; Scene::reduce makes them from full-size ones). With pruned outputs only the requested
/// torques and those of their subtrees are computed; the other entries of data.tau are set to zero.
/// \tparam SceneT  the scene; `model` must be built for it (SceneT::model)
/// \param q    joint angles (rad), Scene::nj
/// \param qd   joint velocities (rad/s), Scene::nj
/// \param qdd  joint accelerations (rad/s^2), Scene::nj
/// \return data.tau, joint torques (N m), Scene::nj
template <class SceneT, class Model, class Q, class QD, class QDD>
inline const typename Model::JointVector& scene_rnea(const Model& model, Data<Model>& data,
                                                     const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                                                     const Eigen::MatrixBase<QDD>& qdd) noexcept {
  using Shape = typename SceneT::shape;
  static_assert(std::is_same_v<typename Model::shape_type, Shape>, "the model was not built for this scene");
  constexpr Terms terms = SceneT::terms;
  if constexpr (!SceneT::prunes_outputs) {
    return rnea<terms>(model, data, q, qd, qdd);
  } else {
    using S = typename Model::scalar_type;
    // gravity enters as an upward acceleration of the base: vd_0 = -R0^T g
    const auto base = detail::base_acceleration(model);

    // the reached joints' cosines and sines first, in a sweep of their own (as detail::joint_cos_sin
    // does for every joint), then the forward pass: full steps in the computed subtrees, motion only
    // along the way to them
    detail::call_flattened([&] {
      detail::static_for<Shape::nj>([&](auto I) {
        constexpr int i = decltype(I)::value;
        if constexpr (SceneT::reached[std::size_t(i)])
          detail::cos_sin(S(model.joint(i).theta + S(q[i])), data.cos_q[std::size_t(i)], data.sin_q[std::size_t(i)]);
      });
    });
    detail::static_for<Shape::nj>([&](auto I) {
      constexpr int i = decltype(I)::value;
      constexpr Twist T = Shape::spec.twist[std::size_t(i)];
      constexpr bool mounted = Shape::spec.mounted[std::size_t(i)];
      constexpr bool massless = Shape::spec.massless[std::size_t(i)];
      if constexpr (SceneT::reached[std::size_t(i)]) {
        S qdi = 0, qddi = 0;
        if constexpr (terms == Terms::Full) qdi = qd[i];
        if constexpr (terms != Terms::GravityOnly) qddi = qdd[i];
        constexpr bool skip_inertia = massless || !SceneT::computed[std::size_t(i)];
        detail::rnea_forward_step<terms, T>(model, data, i, qdi, qddi, base, std::bool_constant<mounted>{},
                                            std::bool_constant<skip_inertia>{});
      }
    });
    // backward pass over the computed subtrees only
    detail::static_for_reverse<Shape::nj>([&](auto I) {
      constexpr int i = decltype(I)::value;
      constexpr Twist T = Shape::spec.twist[std::size_t(i)];
      if constexpr (SceneT::computed[std::size_t(i)])
        detail::rnea_backward_step<T>(model, data, i, std::bool_constant<Shape::spec.mounted[std::size_t(i)]>{});
      else
        data.tau[i] = 0;
    });
    return data.tau;
  }
}

/// The terms a scene's forward dynamics and time stepping use: the scene's own, except that a
/// gravity-only scene keeps the inertia it needs to turn torques into accelerations and drops only the
/// velocity products (as NoCoriolis).
template <class SceneT>
inline constexpr Terms forward_terms = SceneT::terms == Terms::GravityOnly ? Terms::NoCoriolis : SceneT::terms;

/// Forward dynamics in a scene: the accelerations of the scene's joints under the torques tau (all
/// sizes Scene::nj), the locked joints held still, into data.qdd. Every acceleration depends on every
/// torque, so output pruning does not apply here; locks and terms (forward_terms) do.
/// \param q    joint angles (rad), Scene::nj
/// \param qd   joint velocities (rad/s), Scene::nj
/// \param tau  joint torques (N m), Scene::nj
/// \return data.qdd, joint accelerations (rad/s^2), Scene::nj
template <class SceneT, FdMethod method = FdMethod::Articulated, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& scene_forward_dynamics(const Model& model, Data<Model>& data,
                                                                 const Eigen::MatrixBase<Q>& q,
                                                                 const Eigen::MatrixBase<QD>& qd,
                                                                 const Eigen::MatrixBase<Tau>& tau) noexcept {
  static_assert(std::is_same_v<typename Model::shape_type, typename SceneT::shape>,
                "the model was not built for this scene");
  return forward_dynamics<method, forward_terms<SceneT>>(model, data, q, qd, tau);
}

/// One time step in a scene (integrators.hpp) on the scene's joints, with its forward terms: the locked
/// joints stay at their lock angles, so the state, the torques and a servo are all of size Scene::nj.
/// \param tau    joint torques (N m), Scene::nj
/// \param servo  joint-space forces (servo.hpp) added to tau, or nullptr for none; Scene::nj joints
/// \param h      time step (s)
/// \return the status, as `step` gives it; the state is overwritten only on success
template <class SceneT, Integrator integrator, FdMethod method = FdMethod::MassMatrix, class Model>
inline StepStatus scene_step(const Model& model, StepWorkspace<Model>& ws, State<Model>& state,
                             const typename Model::JointVector& tau, const PdServo<std::type_identity_t<Model>>* servo,
                             typename Model::scalar_type h,
                             const StepLimits<typename Model::scalar_type>& limits = {}) noexcept {
  static_assert(std::is_same_v<typename Model::shape_type, typename SceneT::shape>,
                "the model was not built for this scene");
  return step<integrator, method, forward_terms<SceneT>>(model, ws, state, tau, servo, h, limits);
}

/// As above, with no servo.
template <class SceneT, Integrator integrator, FdMethod method = FdMethod::MassMatrix, class Model>
inline StepStatus scene_step(const Model& model, StepWorkspace<Model>& ws, State<Model>& state,
                             const typename Model::JointVector& tau, typename Model::scalar_type h,
                             const StepLimits<typename Model::scalar_type>& limits = {}) noexcept {
  return scene_step<SceneT, integrator, method>(model, ws, state, tau, nullptr, h, limits);
}

/// The named scenes of the seed body. Each has a `name` (as `--scene NAME` takes it), says what it drops
/// (`drops`) and when its torques equal the full model's (`exact_when`); `constrain` turns a full motion
/// into such a one.
namespace scenes {

/// The seed body's legs (group::legs, body.hpp): the joint set UpperBody locks.
inline constexpr auto seed_legs = seed_body.joint_set(group::legs);
/// The seed body's legs and waist: the joint set ArmsOnly locks.
inline constexpr auto seed_legs_and_waist = seed_body.joint_set(group::legs | group::waist);
/// The seed body's arms: the torques ArmTorques asks for.
inline constexpr auto seed_arms = seed_body.joint_set(group::arms);
using SeedSceneSpec = SceneSpec<SeedShape::nj>;  ///< a SceneSpec over the seed body's joints

/// A string literal as a template argument (a C++20 class-type non-type template parameter).
template <std::size_t N>
struct Literal {
  char text[N]{};
  constexpr Literal(const char (&s)[N]) noexcept {  // implicit: a string literal converts
    for (std::size_t i = 0; i < N; ++i) text[i] = s[i];
  }
  constexpr std::string_view view() const noexcept { return {text, N - 1}; }
};

/// A named scene: the seed body's Scene<spec>, with the name `--scene NAME` takes, what it drops and
/// when its torques equal the full model's.
template <SeedSceneSpec spec, Literal name_, Literal drops_, Literal exact_when_>
struct NamedScene : Scene<spec> {
  static constexpr std::string_view name = name_.view();
  static constexpr std::string_view drops = drops_.view();
  static constexpr std::string_view exact_when = exact_when_.view();
};

/// Every joint, every term, every torque: the full model.
using Full = NamedScene<SeedSceneSpec{}, "full", "nothing: every joint, every term, every torque", "always">;

/// The velocity products (Coriolis, centrifugal) dropped, as the seed paper does.
using NoCoriolis =
    NamedScene<SeedSceneSpec{.terms = Terms::NoCoriolis}, "no_coriolis",
               "the velocity products (Coriolis, centrifugal), as the seed paper does", "joint rates are zero">;

/// Gravity torques only (a pose editor).
using StaticPose =
    NamedScene<SeedSceneSpec{.terms = Terms::GravityOnly}, "static_pose",
               "every motion term: gravity torques only (a pose editor)", "joint rates and accelerations are zero">;

/// The legs (joints 1-4, 13-16, 1-based) locked, merged into a fixed pelvis (a seated crowd).
using UpperBody = NamedScene<SeedSceneSpec{.locked = seed_legs}, "upper_body",
                             "the legs: joints 1-4, 13-16 locked, merged into a fixed pelvis (a seated crowd)",
                             "the legs are held still at their lock angles">;

/// Legs and waist (joints 1-6, 13-16, 1-based) locked, merged into a fixed upper body.
using ArmsOnly = NamedScene<SeedSceneSpec{.locked = seed_legs_and_waist}, "arms_only",
                            "legs and waist: joints 1-6, 13-16 locked, merged into a fixed upper body",
                            "legs and waist are held still at their lock angles">;

/// The arm torques (joints 7-12, 1-based) only: left leg skipped, right leg and waist carry motion only.
using ArmTorques =
    NamedScene<SeedSceneSpec{.wanted = seed_arms}, "arm_torques",
               "all torques but the arms' (7-12): left leg skipped, right leg and waist carry motion only",
               "always (for the arm torques)">;

}  // namespace scenes

/// Calls f(scene) with a default-constructed tag of every named scene, in the order above. Each tag
/// has static members name, drops, exact_when, model<S>(description, q_lock), reduce, expand,
/// constrain, outputs(i); run it with scene_rnea<decltype(scene)>.
template <class F>
inline void for_each_named_scene(F&& f) {
  f(scenes::Full{});
  f(scenes::NoCoriolis{});
  f(scenes::StaticPose{});
  f(scenes::UpperBody{});
  f(scenes::ArmsOnly{});
  f(scenes::ArmTorques{});
}

/// Calls f(scene) for the named scene `name`.
/// \return false (and calls nothing) if there is none
template <class F>
inline bool with_named_scene(std::string_view name, F&& f) {
  bool found = false;
  for_each_named_scene([&](auto scene) {
    if (!found && decltype(scene)::name == name) {
      found = true;
      f(scene);
    }
  });
  return found;
}

/// The names of the named scenes, separated by '|' (for help texts and error messages).
inline std::string named_scene_list() {
  std::string out;
  for_each_named_scene([&](auto scene) {
    if (!out.empty()) out += '|';
    out += decltype(scene)::name;
  });
  return out;
}

}  // namespace humandyn
