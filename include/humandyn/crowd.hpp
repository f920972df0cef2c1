// Crowds: many characters of one shape stepped together, W at a time in SIMD lanes (detail/batch.hpp),
// a range at a time for a game's job system, and over threads by a small helper.
//
//   BatchModel<B, Shape>   the model's constants in lanes: one model broadcast, or one model per lane
//                          (a crowd of different bodies); every algorithm runs on it as on a Model
//   CrowdView<T>           a crowd as the game keeps it, character after character: q, q̇, τ, servo, status
//   step_crowd             the checked step of characters [begin, end): each character's status is the
//                          scalar step's, a failing character's state is left as it was, the others step
//   step_crowd_backward_euler  backward Euler, not batched: the scalar step, character after character,
//                              each continuing its last step (BackwardEulerMemory) or from a fresh start
//   inverse_dynamics_crowd rnea of characters [begin, end)
//   split_crowd            [0, n) cut into whole batches over std::threads, one workspace per thread
//   CrowdThreads           split_crowd's threads kept between calls
//
// Lane l of every batched result equals the scalar algorithm's result for character l (tests/test_crowd.cpp).
#pragma once

#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/detail/batch.hpp"
#include "humandyn/integrators.hpp"
#include "humandyn/model.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <thread>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace humandyn {

namespace detail {

// lane l of a batch, of a vector or matrix of batches, set from or read into plain values
template <class B>
inline void put_lane(B& dst, int l, typename lanes<B>::value_type v) noexcept {
  lanes<B>::set(dst, l, v);
}
template <class B, int R, int C, int O, int MR, int MC, class Src>
inline void put_lane(Eigen::Matrix<B, R, C, O, MR, MC>& dst, int l, const Eigen::MatrixBase<Src>& src) noexcept {
  for (Eigen::Index c = 0; c < dst.cols(); ++c)
    for (Eigen::Index r = 0; r < dst.rows(); ++r) lanes<B>::set(dst(r, c), l, src(r, c));
}
template <class B, class T>
inline void put_lane(Pose<B>& dst, int l, const Pose<T>& src) noexcept {
  put_lane(dst.R, l, src.R);
  put_lane(dst.p, l, src.p);
}
template <class B, class T>
inline void put_lane(RigidBodyInertia<B>& dst, int l, const RigidBodyInertia<T>& src) noexcept {
  put_lane(dst.mass, l, src.mass);
  put_lane(dst.com, l, src.com);
  put_lane(dst.inertia, l, src.inertia);
}
template <class B, class T>
inline void put_lane(JointConstants<B>& dst, int l, const JointConstants<T>& src) noexcept {
  dst.parent = src.parent;
  dst.twist = src.twist;
  dst.mounted = src.mounted;
  std::apply(
      [&](auto&... to) {
        std::apply([&](const auto&... from) { (put_lane(to, l, from), ...); }, JointConstants<T>::numbers(src));
      },
      JointConstants<B>::numbers(dst));
}

}  // namespace detail

/// Lane l of a batched result (a vector or matrix of batches) as plain values.
/// \return a matrix of the lanes' value type, of the same size
template <class Derived>
auto lane(const Eigen::MatrixBase<Derived>& m, int l) {
  using B = typename Derived::Scalar;
  using T = typename detail::lanes<B>::value_type;
  Eigen::Matrix<T, Derived::RowsAtCompileTime, Derived::ColsAtCompileTime> out(m.rows(), m.cols());
  for (Eigen::Index c = 0; c < m.cols(); ++c)
    for (Eigen::Index r = 0; r < m.rows(); ++r) out(r, c) = detail::lanes<B>::get(m(r, c), l);
  return out;
}

/// A model's constants in SIMD lanes, for the algorithms to run on W characters at once (lane l being
/// character l). It offers what the algorithms read of a Model (joint constants, gravity, base pose and
/// body) and is built from validated scalar models: one broadcast to every lane, or one per lane (each
/// lane a body of its own size and mass; all of the same static shape and mounts).
/// \tparam B      a batch, NativeBatch<double> or FixedBatch<float, 16> ... (detail/batch.hpp)
/// \tparam Shape  a static shape (SeedShape, BodyShape<table>)
template <class B, class Shape = SeedShape>
class BatchModel {
 public:
  using scalar_type = B;
  using value_type = typename detail::lanes<B>::value_type;
  using shape_type = Shape;
  using LaneModel = Model<value_type, Shape>;
  static constexpr int nj = Shape::nj;
  static constexpr int width = detail::lanes<B>::width;
  using JointVector = Eigen::Matrix<B, nj, 1>;
  static_assert(Shape::is_static, "a batch needs a shape known at compile time");

  struct Description {
    RigidBodyInertia<B> base_body;  // the stance foot, in the base frame
  };

  /// Every lane the same model ("one model, many states").
  explicit BatchModel(const LaneModel& model) {
    for (int l = 0; l < width; ++l) put(l, model);
  }

  /// Lane l from *models[l] ("a crowd of different bodies").
  /// \throws ModelError when the models differ in a joint's mount (the rest of the shape is the type's)
  explicit BatchModel(std::span<const LaneModel* const> models) {
    if (int(models.size()) != width) throw ModelError("a batch model needs one model per lane");
    for (int l = 0; l < width; ++l) {
      for (int i = 0; i < nj; ++i)
        if (models[std::size_t(l)]->joint(i).mounted != models[0]->joint(i).mounted)
          throw ModelError("joint '" + models[0]->joint_name(i) + "' is mounted in one lane's model only");
      put(l, *models[std::size_t(l)]);
    }
  }

  int size() const noexcept { return nj; }
  const JointConstants<B>& joint(int i) const noexcept { return joints_[std::size_t(i)]; }
  const Vec3<B>& gravity() const noexcept { return gravity_; }
  const Pose<B>& base_pose() const noexcept { return base_pose_; }
  const Description& description() const noexcept { return desc_; }

 private:
  void put(int l, const LaneModel& m) {
    for (int i = 0; i < nj; ++i) detail::put_lane(joints_[std::size_t(i)], l, m.joint(i));
    detail::put_lane(gravity_, l, m.gravity());
    detail::put_lane(base_pose_, l, m.base_pose());
    detail::put_lane(desc_.base_body, l, m.description().base_body);
  }

  std::array<JointConstants<B>, std::size_t(nj)> joints_{};
  Vec3<B> gravity_ = Vec3<B>::Zero();
  Pose<B> base_pose_{};
  Description desc_{};
};

/// The joint-space servo of every character of a crowd (servo.hpp's PdServo fields), each array
/// character after character, size x nj; a null view for none.
template <class T>
struct CrowdServo {
  const T *kp = nullptr, *kd = nullptr, *q_ref = nullptr, *qd_ref = nullptr;  // N m/rad, N m s/rad, rad, rad/s
  const T *damping = nullptr, *q_min = nullptr, *q_max = nullptr,
          *limit_stiffness = nullptr;  // N m s/rad, rad, N m/rad
};

/// A crowd as a game keeps it: per character nj angles, velocities and torques, one character after the
/// other (character c's joint i at [c nj + i]), and one status each. Plain pointers: the same view
/// serves the header-only code and the per-instruction-set kernels.
template <class T>
struct CrowdView {
  std::size_t size = 0;                  // characters
  T* q = nullptr;                        // rad, size x nj
  T* qd = nullptr;                       // rad/s, size x nj
  const T* tau = nullptr;                // motor torques (N m), size x nj, held over the step
  const CrowdServo<T>* servo = nullptr;  // joint-space forces added to tau, or nullptr for none
  StepStatus* status = nullptr;          // receives each stepped character's status, size
};

/// Character c's servo of a crowd as the scalar step (integrators.hpp's `step`) takes it.
/// \param servo  the crowd's servo arrays (character c's joint i at [c nj + i])
/// \param c      the character
/// \param s      receives its gains (N m/rad, N m s/rad), references (rad, rad/s), damping (N m s/rad) and
///               limits (rad, N m/rad); a servo of a model of nj joints
template <class Model>
inline void character_servo(const CrowdServo<typename Model::scalar_type>& servo, std::size_t c,
                            PdServo<Model>& s) noexcept {
  using Map = Eigen::Map<const typename PdServo<Model>::JointVector>;
  const Eigen::Index n = s.kp.size();
  for (auto [dst, src] : {std::pair{&s.kp, servo.kp},
                          {&s.kd, servo.kd},
                          {&s.q_ref, servo.q_ref},
                          {&s.qd_ref, servo.qd_ref},
                          {&s.damping, servo.damping},
                          {&s.q_min, servo.q_min},
                          {&s.q_max, servo.q_max},
                          {&s.limit_stiffness, servo.limit_stiffness}})
    *dst = Map(src + c * std::size_t(n), n);
}

namespace detail {

// One character's servo seen through maps, for first_invalid_servo_joint.
template <class T, int nj>
struct CharacterServo {
  using Map = Eigen::Map<const Eigen::Matrix<T, nj, 1>>;
  Map kp, kd, q_ref, qd_ref, damping, q_min, q_max, limit_stiffness;
  CharacterServo(const CrowdServo<T>& s, std::size_t c)
      : kp(s.kp + c * nj),
        kd(s.kd + c * nj),
        q_ref(s.q_ref + c * nj),
        qd_ref(s.qd_ref + c * nj),
        damping(s.damping + c * nj),
        q_min(s.q_min + c * nj),
        q_max(s.q_max + c * nj),
        limit_stiffness(s.limit_stiffness + c * nj) {}
};

// Between the crowd's layout (a character's joints side by side) and the lanes' (a joint's characters
// side by side) the W x W blocks are transposed in registers: log2 W stages, each swapping the
// off-diagonal blocks of half its size by two-source shuffles (W log2 W in all, against W^2 scalar
// moves through memory, whose store-to-load stalls cost more than the step's dynamics). Native batches
// only, W x W at a time; the joints left over (nj not a multiple of W) and other batches go lane by lane.
template <class B>
constexpr bool transposes_in_registers = std::is_same_v<B, NativeBatch<typename B::value_type>> &&
                                         sizeof(B) == B::size() * sizeof(typename B::value_type);

template <std::size_t h, class V, std::size_t W, std::size_t... J>
inline void transpose_stage(std::array<V, W>& v, std::index_sequence<J...>) noexcept {
  for (std::size_t i = 0; i < W; ++i)
    if ((i & h) == 0) {
      const V a = v[i], b = v[i + h];
      v[i] = __builtin_shufflevector(a, b, ((J & h) ? W + J - h : J)...);
      v[i + h] = __builtin_shufflevector(a, b, ((J & h) ? W + J : J + h)...);
    }
}

template <class T, std::size_t W>
struct vector_of {  // the compiler's vector of W T's, which its shuffles take
  using type [[gnu::vector_size(W * sizeof(T))]] = T;
};

template <class B, std::size_t W, std::size_t... S>
inline void transpose(std::array<B, W>& rows, std::index_sequence<S...>) noexcept {
  using V = typename vector_of<typename B::value_type, W>::type;
  std::array<V, W> v;
  for (std::size_t l = 0; l < W; ++l) v[l] = std::bit_cast<V>(rows[l]);
  (transpose_stage<(W >> (S + 1))>(v, std::make_index_sequence<W>{}), ...);  // blocks of W/2, W/4, ..., 1
  for (std::size_t l = 0; l < W; ++l) rows[l] = std::bit_cast<B>(v[l]);
}

template <class B, std::size_t W>
inline void transpose(std::array<B, W>& rows) noexcept {
  static_assert(std::has_single_bit(W), "a power-of-two width");
  transpose(rows, std::make_index_sequence<std::size_t(std::bit_width(W)) - 1>{});
}

// Joint i of lane l from src[(first + l) nj + i] where live[l], else `rest`.
template <class B, int nj, class T, std::size_t W>
inline void gather(Eigen::Matrix<B, nj, 1>& dst, const T* src, std::size_t first, const std::array<bool, W>& live,
                   T rest) noexcept {
  int j0 = 0;
  if constexpr (transposes_in_registers<B>)
    for (; j0 + int(W) <= nj; j0 += int(W)) {
      std::array<B, W> rows;
      for (std::size_t l = 0; l < W; ++l)
        rows[l] = live[l] ? B(src + (first + l) * nj + std::size_t(j0), stdx::element_aligned) : B(rest);
      transpose(rows);
      for (std::size_t i = 0; i < W; ++i) dst[j0 + int(i)] = rows[i];
    }
  for (int i = j0; i < nj; ++i)
    dst[i] = B([&](auto l) { return live[l] ? src[(first + l) * nj + std::size_t(i)] : rest; });
}

// Lane l of every joint of v into out[l][0, nj) where out[l] is not null: gather's inverse.
template <class B, int nj, class T, std::size_t W>
inline void scatter(const Eigen::Matrix<B, nj, 1>& v, const std::array<T*, W>& out) noexcept {
  int j0 = 0;
  if constexpr (transposes_in_registers<B>)
    for (; j0 + int(W) <= nj; j0 += int(W)) {
      std::array<B, W> rows;
      for (std::size_t i = 0; i < W; ++i) rows[i] = v[j0 + int(i)];
      transpose(rows);
      for (std::size_t l = 0; l < W; ++l)
        if (out[l]) rows[l].copy_to(out[l] + j0, stdx::element_aligned);
    }
  for (int i = j0; i < nj; ++i)
    for (std::size_t l = 0; l < W; ++l)
      if (out[l]) out[l][i] = v[i][int(l)];
}

// The lanes whose input passes check_step_input (integrators.hpp): the same conditions on the angles,
// velocities, torques and servo, tested in every lane at once.
template <class B, int nj, class Servo, class T>
inline typename lanes<B>::mask passes_step_input(const Eigen::Matrix<B, nj, 1>& q, const Eigen::Matrix<B, nj, 1>& qd,
                                                 const Eigen::Matrix<B, nj, 1>& tau, const Servo* servo,
                                                 const StepLimits<T>& limits) noexcept {
  using stdx::abs;
  using stdx::isfinite;
  const B max_q(limits.max_abs_q), max_qd(limits.max_abs_qd);
  typename lanes<B>::mask ok(true);
  for (int i = 0; i < nj; ++i) ok = ok && isfinite(q[i]) && isfinite(qd[i]) && isfinite(tau[i]);
  if (servo)
    for (int i = 0; i < nj; ++i) {
      const Servo& s = *servo;
      ok = ok && isfinite(s.kp[i]) && isfinite(s.kd[i]) && isfinite(s.q_ref[i]) && isfinite(s.qd_ref[i]) &&
           isfinite(s.damping[i]) && isfinite(s.limit_stiffness[i]);
      ok = ok && s.kp[i] >= 0 && s.kd[i] >= 0 && s.damping[i] >= 0 && s.limit_stiffness[i] >= 0;
      ok = ok && s.q_min[i] <= s.q_max[i] && (s.q_min[i] < s.q_max[i] || isfinite(s.q_min[i]));  // (NaN: false)
      ok = ok && !(abs(s.q_ref[i]) > max_q || abs(s.qd_ref[i]) > max_qd);  // (a NaN limit: the result's check)
    }
  return ok;
}

// The lanes whose candidate end state passes check_step_result: angles and velocities finite and within
// the limits, tested in every lane at once.
template <class B, int nj, class T>
inline typename lanes<B>::mask passes_step_result(const Eigen::Matrix<B, nj, 1>& q, const Eigen::Matrix<B, nj, 1>& qd,
                                                  const StepLimits<T>& limits) noexcept {
  using stdx::abs;
  using stdx::isfinite;
  const B max_q(limits.max_abs_q), max_qd(limits.max_abs_qd);
  typename lanes<B>::mask ok(true);
  for (int i = 0; i < nj; ++i)
    ok = ok && isfinite(q[i]) && isfinite(qd[i]) && abs(qd[i]) <= max_qd && abs(q[i]) <= max_q;
  return ok;
}

}  // namespace detail

/// Every buffer step_crowd and inverse_dynamics_crowd write for one batch of W characters; one per thread.
template <class B, class Shape = SeedShape>
struct CrowdWorkspace {
  using BModel = BatchModel<B, Shape>;
  using T = typename BModel::value_type;
  static constexpr int nj = BModel::nj;
  explicit CrowdWorkspace(const BModel& model) : step(model), x(model), servo(model) {
    tau.setZero();
    qdd.setZero();
  }
  StepWorkspace<BModel> step;  // the dynamics' buffers in lanes
  State<BModel> x;             // the batch's start state
  typename BModel::JointVector tau, qdd;
  PdServo<BModel> servo;
  std::array<bool, std::size_t(BModel::width)> live{};  // per lane: a character that passed the input checks
  T q[BModel::width][nj], qd[BModel::width][nj];        // a failing lane's candidate end state, to check it alone
};

/// The checked step (integrators.hpp's `step`) of characters [begin, end) of a crowd, W at a time in
/// the lanes of `model`: character c's status is what step() would return for it alone, and its state
/// is written only when that status is ok. A crowd whose size is not a multiple of W leaves the last
/// batch's spare lanes at rest; they are never written out.
/// \tparam integrator  SemiImplicitEuler, RungeKutta4 or ImplicitPD (backward Euler: step_crowd_backward_euler)
/// \param model   lane l's constants serve the characters begin + l, begin + W + l, ...
/// \param ws      workspace made from `model`, not shared between threads
/// \param crowd   the characters; q and qd (rad, rad/s) overwritten where the step succeeds
/// \param begin, end  the range of characters (end <= crowd.size)
/// \param h       time step (s); limits as for step(). No allocation, no exception.
template <Integrator integrator, Terms terms = Terms::Full, class B, class Shape>
inline void step_crowd(const BatchModel<B, Shape>& model, CrowdWorkspace<B, Shape>& ws,
                       const CrowdView<typename BatchModel<B, Shape>::value_type>& crowd, std::size_t begin,
                       std::size_t end, typename BatchModel<B, Shape>::value_type h,
                       const StepLimits<typename BatchModel<B, Shape>::value_type>& limits = {}) noexcept {
  using T = typename BatchModel<B, Shape>::value_type;
  static_assert(integrator != Integrator::BackwardEuler,
                "step_crowd: backward Euler is not batched (step_crowd_backward_euler steps a crowd by it)");
  using L = detail::lanes<B>;
  constexpr int W = L::width, nj = Shape::nj;
  using Vector = Eigen::Matrix<T, nj, 1>;
  using Map = Eigen::Map<Vector>;
  using ConstMap = Eigen::Map<const Vector>;
  constexpr T inf = std::numeric_limits<T>::infinity();
  if (const StepStatus st = detail::check_time_step(h); !st.ok()) {  // (every character refused alike)
    for (std::size_t c = begin; c < end; ++c) crowd.status[c] = st;
    return;
  }
  for (std::size_t first = begin; first < end; first += W) {
    // the batch's characters in the lanes; a lane past `end` rests (zero state, no servo)
    for (int l = 0; l < W; ++l) ws.live[std::size_t(l)] = first + std::size_t(l) < end;
    const auto gather_all = [&] {
      detail::gather(ws.x.q, crowd.q, first, ws.live, T(0));
      detail::gather(ws.x.qd, crowd.qd, first, ws.live, T(0));
      detail::gather(ws.tau, crowd.tau, first, ws.live, T(0));
      if (const auto* s = crowd.servo) {
        detail::gather(ws.servo.kp, s->kp, first, ws.live, T(0));
        detail::gather(ws.servo.kd, s->kd, first, ws.live, T(0));
        detail::gather(ws.servo.q_ref, s->q_ref, first, ws.live, T(0));
        detail::gather(ws.servo.qd_ref, s->qd_ref, first, ws.live, T(0));
        detail::gather(ws.servo.damping, s->damping, first, ws.live, T(0));
        detail::gather(ws.servo.q_min, s->q_min, first, ws.live, -inf);
        detail::gather(ws.servo.q_max, s->q_max, first, ws.live, inf);
        detail::gather(ws.servo.limit_stiffness, s->limit_stiffness, first, ws.live, T(0));
      }
    };
    gather_all();

    // the input checks in the lanes at once; a character that fails them is checked alone for its
    // status (the first bad quantity and joint, as step() names it) and its lane rests
    const auto passed = detail::passes_step_input(ws.x.q, ws.x.qd, ws.tau, crowd.servo ? &ws.servo : nullptr, limits);
    bool any = false, rested = false;
    for (int l = 0; l < W; ++l) {
      const std::size_t c = first + std::size_t(l);
      if (!ws.live[std::size_t(l)]) continue;
      if (passed[l]) {
        crowd.status[c] = {};
      } else {
        std::optional<detail::CharacterServo<T, nj>> servo;
        if (crowd.servo) servo.emplace(*crowd.servo, c);
        crowd.status[c] = detail::check_step_input(ConstMap(crowd.q + c * nj), ConstMap(crowd.qd + c * nj),
                                                   ConstMap(crowd.tau + c * nj), servo ? &*servo : nullptr, h, limits);
        ws.live[std::size_t(l)] = crowd.status[c].ok();
        rested = rested || !crowd.status[c].ok();
      }
      any = any || ws.live[std::size_t(l)];
    }
    if (!any) continue;
    if (rested) gather_all();  // (again, the refused characters' lanes now at rest)

    struct {  // the torques held over the step, each character's already checked
      const typename BatchModel<B, Shape>::JointVector& tau;
      int bad_joint = -1;
      const typename BatchModel<B, Shape>::JointVector& operator()(B) const noexcept { return tau; }
    } held{ws.tau};
    detail::advance<integrator, FdMethod::MassMatrix, terms>(model, ws.step, ws.x, held,
                                                             crowd.servo ? &ws.servo : nullptr, B(h));

    // the candidate, checked as step() checks it in the lanes at once, written straight out where it
    // passes; a character that fails is checked alone, from the workspace, for its status
    const auto result_passed = detail::passes_step_result(ws.step.next.q, ws.step.next.qd, limits);
    std::array<T*, std::size_t(W)> q_out{}, qd_out{};
    for (int l = 0; l < W; ++l) {
      const auto k = std::size_t(l);
      const std::size_t c = first + k;
      if (!ws.live[k]) continue;
      q_out[k] = result_passed[l] ? crowd.q + c * nj : ws.q[l];
      qd_out[k] = result_passed[l] ? crowd.qd + c * nj : ws.qd[l];
    }
    detail::scatter(ws.step.next.q, q_out);
    detail::scatter(ws.step.next.qd, qd_out);
    bool pivots = false;  // whether ws.step.data holds the pivots of the step's matrix at the batch's start
    for (int l = 0; l < W; ++l) {
      const std::size_t c = first + std::size_t(l);
      if (!ws.live[std::size_t(l)] || result_passed[l]) continue;
      const ConstMap q(ws.q[l]), qd(ws.qd[l]);
      crowd.status[c] = detail::check_step_result(q, qd, limits);
      if (crowd.status[c].error == StepError::NonFinite) {  // a NaN where M is singular: that joint, as step()
        if (!pivots) {
          detail::factorize_step_matrix<integrator>(model, ws.step, ws.x, crowd.servo ? &ws.servo : nullptr, B(h));
          pivots = true;
        }
        if (const int j = singular_pivot_joint(nj, [&](int i) { return ws.step.data.D[i][l]; }); j >= 0)
          crowd.status[c] = {StepError::SingularMassMatrix, Quantity::None, j};
      }
      if (!crowd.status[c].ok()) continue;
      Map(crowd.q + c * nj) = q;
      Map(crowd.qd + c * nj) = qd;
    }
  }
}

/// What backward Euler carries from one step of a character to its next (integrators.hpp, StepWorkspace's
/// `carried` fields and its Jacobian's factorisation; docs/stability.md, "Continuing steps"), kept per
/// character for step_crowd_backward_euler. Made from the model, owned by the caller, one per character;
/// about 5 KB for the 16-joint body in double.
template <class Model>
struct BackwardEulerMemory {
  using S = typename Model::scalar_type;
  using JointVector = typename Model::JointVector;
  explicit BackwardEulerMemory(const Model& model) : end(model), lu(model) {
    for (auto* v : {&qdd, &qdd_1, &qdd_2}) v->setZero(model.size());
  }
  const Model* carried_model = nullptr;  // the model of the last step; nullptr: nothing carried (a new
                                         // character, or its last step failed)
  State<Model> end;                      // the last step's end state
  JointVector qdd, qdd_1, qdd_2;         // the q̈ of the last step, of the one before, ...
  S energy = S(0);                       // the body's energy at `end` (J)
  S h = S(0);                            // the length of the step that reached qdd (s)
  int known = 0;                         // how many of qdd_1, qdd_2 belong to steps of that length
  JacobianFactorisation<Model> lu;       // the Jacobian's factorisation
  S jacobian_h = S(0);                   // its substep length (s; 0: none)
  bool jacobian_with_servo = false;      // whether it holds the servo's gains
};

namespace detail {

// The fields a character's memory keeps, each with the workspace's it stands for: one list for both ways.
template <class Workspace, class Memory, class F>
inline void for_each_carried(Workspace& ws, Memory& m, F&& f) noexcept {
  f(ws.carried, m.end);
  f(ws.carried_qdd, m.qdd);
  f(ws.carried_qdd_1, m.qdd_1);
  f(ws.carried_qdd_2, m.qdd_2);
  f(ws.carried_energy, m.energy);
  f(ws.carried_h, m.h);
  f(ws.carried_known, m.known);
  f(ws.lu, m.lu);
  f(ws.jacobian_h, m.jacobian_h);
}

// Character memory into the workspace: what step() finds there after that character's last step, the
// crowd's scratch servo standing for the character's own (a Jacobian made with a servo serves the steps
// with one, whatever its gains, as for step() with one PdServo object changed in place).
template <class Model>
inline void recall(const Model& model, StepWorkspace<Model>& ws, const BackwardEulerMemory<Model>& m,
                   const PdServo<Model>& servo) noexcept {
  if (m.carried_model != &model) {  // (nothing carried, or a step of another model object: this one starts afresh)
    ws.forget();
    return;
  }
  for_each_carried(ws, m, [](auto& w, const auto& kept) noexcept { w = kept; });
  ws.carried_model = &model;
  ws.jacobian_servo = m.jacobian_with_servo ? &servo : nullptr;
}

// The workspace's carried step into the character's memory.
template <class Model>
inline void remember(const Model& model, const StepWorkspace<Model>& ws, BackwardEulerMemory<Model>& m) noexcept {
  m.carried_model = ws.carried_model == &model ? &model : nullptr;
  if (!m.carried_model) return;  // (a step after it starts afresh, its Jacobian too)
  for_each_carried(ws, m, [](const auto& w, auto& kept) noexcept { kept = w; });
  m.jacobian_with_servo = ws.jacobian_servo != nullptr;
}

}  // namespace detail

/// Backward Euler (integrators.hpp) for characters [begin, end) of a crowd, one character after the other
/// by the scalar step: Newton's method takes as many corrections and substeps as each character needs,
/// which lanes stepping together cannot share. With `memory` (one per character), each character's step
/// continues its last one as step() does with a workspace of its own (its energy, a first q̈ extrapolated
/// from its last steps and its Jacobian, about half the cost of a fresh step); without, each starts afresh
/// (ws.forget(): its first q̈ from the implicit PD step). Either way a character's result does not depend on
/// the characters stepped before it, nor on how the crowd is split over threads: it is what step() gives
/// that character from a workspace of its own (kept over its steps with memory, fresh without).
/// \param model   the model of every character
/// \param ws      workspace made from `model`; it, x and servo are not shared between threads
/// \param x       scratch: receives each character's state in turn
/// \param servo   scratch, a servo of `model`: receives each character's (when crowd.servo is set)
/// \param crowd   the characters; q and qd (rad, rad/s) overwritten where the step succeeds, status each
/// \param memory  empty, or each character's memory (memory[c] for character c, at least `end` of them)
/// \param begin, end  the range of characters (end <= crowd.size)
/// \param h       time step (s); limits as for step(). No exception; no allocation for a static shape.
template <class Model>
inline void step_crowd_backward_euler(const Model& model, StepWorkspace<Model>& ws, State<Model>& x,
                                      PdServo<Model>& servo, const CrowdView<typename Model::scalar_type>& crowd,
                                      std::span<BackwardEulerMemory<Model>> memory, std::size_t begin, std::size_t end,
                                      typename Model::scalar_type h,
                                      const StepLimits<typename Model::scalar_type>& limits = {}) noexcept {
  using Vector = typename Model::JointVector;
  const auto nj = std::size_t(model.size());
  const Eigen::Index n = model.size();
  eigen_assert(memory.empty() || memory.size() >= end);
  const PdServo<Model>* character = crowd.servo ? &servo : nullptr;
  for (std::size_t c = begin; c < end; ++c) {
    x.q = Eigen::Map<const Vector>(crowd.q + c * nj, n);
    x.qd = Eigen::Map<const Vector>(crowd.qd + c * nj, n);
    if (crowd.servo) character_servo(*crowd.servo, c, servo);
    if (memory.empty())
      ws.forget();
    else
      detail::recall(model, ws, memory[c], servo);
    crowd.status[c] = step<Integrator::BackwardEuler>(model, ws, x, Eigen::Map<const Vector>(crowd.tau + c * nj, n),
                                                      character, h, limits);
    if (!memory.empty()) detail::remember(model, ws, memory[c]);
    if (!crowd.status[c].ok()) continue;
    Eigen::Map<Vector>(crowd.q + c * nj, n) = x.q;
    Eigen::Map<Vector>(crowd.qd + c * nj, n) = x.qd;
  }
}

/// As above, each character's step from a fresh start (no memory).
template <class Model>
inline void step_crowd_backward_euler(const Model& model, StepWorkspace<Model>& ws, State<Model>& x,
                                      PdServo<Model>& servo, const CrowdView<typename Model::scalar_type>& crowd,
                                      std::size_t begin, std::size_t end, typename Model::scalar_type h,
                                      const StepLimits<typename Model::scalar_type>& limits = {}) noexcept {
  step_crowd_backward_euler(model, ws, x, servo, crowd, std::span<BackwardEulerMemory<Model>>{}, begin, end, h, limits);
}

/// Full inverse dynamics (rnea) of characters [begin, end) of a crowd, W at a time in the lanes of `model`.
/// \param q, qd, qdd  angles (rad), velocities (rad/s), accelerations (rad/s^2): character c's joint i
///                    at [c nj + i]
/// \param tau         receives the torques (N m), in the same layout, for characters [begin, end) only
/// No allocation, no exception; non-finite input gives non-finite torques for that character alone.
template <class B, class Shape>
inline void inverse_dynamics_crowd(const BatchModel<B, Shape>& model, CrowdWorkspace<B, Shape>& ws,
                                   const typename BatchModel<B, Shape>::value_type* q,
                                   const typename BatchModel<B, Shape>::value_type* qd,
                                   const typename BatchModel<B, Shape>::value_type* qdd,
                                   typename BatchModel<B, Shape>::value_type* tau, std::size_t begin,
                                   std::size_t end) noexcept {
  using T = typename BatchModel<B, Shape>::value_type;
  using L = detail::lanes<B>;
  constexpr int W = L::width, nj = Shape::nj;
  for (std::size_t first = begin; first < end; first += W) {
    for (int l = 0; l < W; ++l) ws.live[std::size_t(l)] = first + std::size_t(l) < end;
    detail::gather(ws.x.q, q, first, ws.live, T(0));
    detail::gather(ws.x.qd, qd, first, ws.live, T(0));
    detail::gather(ws.qdd, qdd, first, ws.live, T(0));
    std::array<T*, std::size_t(W)> out{};
    for (int l = 0; l < W && first + std::size_t(l) < end; ++l)
      out[std::size_t(l)] = tau + (first + std::size_t(l)) * nj;
    detail::scatter(rnea(model, ws.step.data, ws.x.q, ws.x.qd, ws.qdd), out);
  }
}

namespace detail {

// Characters [0, n) in whole batches of `width` over up to `threads` ranges: how many ranges, and range t.
inline std::size_t crowd_ranges(std::size_t n, int threads, int width) noexcept {
  const std::size_t batches = (n + std::size_t(width) - 1) / std::size_t(width);
  return std::max<std::size_t>(1, std::min(std::size_t(std::max(1, threads)), batches));
}
inline std::pair<std::size_t, std::size_t> crowd_range(std::size_t n, int width, std::size_t ranges,
                                                       std::size_t t) noexcept {
  const std::size_t batches = (n + std::size_t(width) - 1) / std::size_t(width);
  const std::size_t b0 = batches * t / ranges, b1 = batches * (t + 1) / ranges;
  return {std::min(n, b0 * std::size_t(width)), std::min(n, b1 * std::size_t(width))};
}

}  // namespace detail

/// Cuts characters [0, n) into `threads` contiguous ranges of whole batches of `width` and calls
/// f(t, begin, end) for range t, on threads - 1 new std::threads and the calling one; returns when all
/// are done. Each range's characters are independent, so any split gives bitwise the same states.
/// For the command line and the benchmarks; a game hands the ranges to its own job system instead.
/// Starting the threads costs tens of microseconds per call: CrowdThreads keeps them between calls.
template <class F>
void split_crowd(std::size_t n, int threads, int width, F&& f) {
  const std::size_t ranges = detail::crowd_ranges(n, threads, width);
  std::vector<std::thread> pool;
  pool.reserve(ranges - 1);
  for (std::size_t t = 1; t < ranges; ++t)
    pool.emplace_back([&, t] {
      const auto [b, e] = detail::crowd_range(n, width, ranges, t);
      f(int(t), b, e);
    });
  const auto [b, e] = detail::crowd_range(n, width, ranges, 0);
  f(0, b, e);
  for (auto& th : pool) th.join();
}

/// split_crowd's threads kept between calls, for a program without a job system of its own: made once
/// (threads - 1 workers), then run() cuts [0, n) and calls f(t, begin, end) exactly as split_crowd does,
/// without starting a thread. The program makes and ends it; no algorithm of the engine starts one. One
/// run() at a time (a second one while the first runs, or f calling run(), terminates the program, as f
/// throwing does: nothing is left half done).
///
/// Between runs a worker polls for the next one for `spin` before it sleeps, and run() polls as long for
/// the last range before it sleeps: waking a sleeping thread takes tens of microseconds on a virtual
/// machine, as much as a whole range of a 1000-character crowd's inverse dynamics. A game that runs the
/// crowd once per frame spends up to `spin` of each worker's core per frame on it, and with more threads
/// than cores polling threads take time from working ones; 0 (or less) sleeps at once, and no spin is
/// taken as longer than one second.
class CrowdThreads {
 public:
  /// \param threads  ranges per run, the calling thread included (below 1: 1)
  /// \param spin     how long a waiting thread polls before it sleeps
  /// \throws std::system_error when a thread cannot be started (those started are stopped first)
  explicit CrowdThreads(int threads, std::chrono::nanoseconds spin = std::chrono::microseconds(200))
      : count_(std::max(1, threads)),
        spin_(std::clamp(spin, std::chrono::nanoseconds(0), std::chrono::nanoseconds(std::chrono::seconds(1)))) {
    workers_.reserve(std::size_t(count_ - 1));
    try {
      for (int t = 1; t < count_; ++t) workers_.emplace_back([this, t] { work(t); });
    } catch (...) {
      stop();
      throw;
    }
  }
  ~CrowdThreads() { stop(); }
  CrowdThreads(const CrowdThreads&) = delete;
  CrowdThreads& operator=(const CrowdThreads&) = delete;

  int size() const noexcept { return count_; }

  /// As split_crowd(n, size(), width, f), on the kept threads; returns when every range is done.
  template <class F>
  void run(std::size_t n, int width, F&& f) noexcept {
    if (busy_.exchange(true, std::memory_order_acquire)) std::terminate();  // (one run at a time)
    using Fn = std::remove_reference_t<F>;
    job_ = {[](void* g, int t, std::size_t b, std::size_t e) { (*static_cast<Fn*>(g))(t, b, e); },
            const_cast<void*>(static_cast<const void*>(std::addressof(f))), n, width,
            detail::crowd_ranges(n, count_, width)};
    pending_.store(count_ - 1, std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);  // (publishes job_)
    generation_.notify_all();
    range(0);
    poll([&] { return pending_.load(std::memory_order_acquire) == 0; });
    for (int left; (left = pending_.load(std::memory_order_acquire)) != 0;)
      pending_.wait(left, std::memory_order_acquire);
    busy_.store(false, std::memory_order_release);
  }

 private:
  struct Job {
    void (*call)(void*, int, std::size_t, std::size_t) = nullptr;
    void* f = nullptr;
    std::size_t n = 0;
    int width = 1;
    std::size_t ranges = 1;
  };

  void range(int t) {
    if (std::size_t(t) >= job_.ranges) return;
    const auto [b, e] = detail::crowd_range(job_.n, job_.width, job_.ranges, std::size_t(t));
    job_.call(job_.f, t, b, e);
  }

  void stop() noexcept {
    stop_.store(true, std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);
    generation_.notify_all();
    for (auto& th : workers_) th.join();
  }

  // Polls until done() or spin_ has passed (the clock read every 64 polls).
  template <class Done>
  void poll(Done&& done) const noexcept {
    if (spin_.count() == 0) return;
    const auto until = std::chrono::steady_clock::now() + spin_;
    for (unsigned k = 1; !done(); ++k) {
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
      if (k % 64 == 0 && std::chrono::steady_clock::now() >= until) return;
    }
  }

  void work(int t) {
    std::uint64_t seen = 0;
    for (;;) {
      poll([&] { return generation_.load(std::memory_order_relaxed) != seen; });
      generation_.wait(seen, std::memory_order_acquire);
      seen = generation_.load(std::memory_order_acquire);
      if (stop_.load(std::memory_order_relaxed)) return;
      range(t);
      if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) pending_.notify_one();
    }
  }

  int count_;
  std::chrono::nanoseconds spin_;
  Job job_{};
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<int> pending_{0};
  std::atomic<bool> stop_{false}, busy_{false};
  std::vector<std::thread> workers_;  // (last: they stop before the members they read go)
};

}  // namespace humandyn
