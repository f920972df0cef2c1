// One loop over the joints for every shape. A static shape unrolls it and hands each joint's twist,
// mount and mass facts to the body as compile-time constants; a dynamic shape loops and dispatches on
// the twist class at run time, so both run the same per-joint code.
#pragma once

#include "humandyn/detail/batch.hpp"
#include "humandyn/detail/dh.hpp"
#include "humandyn/detail/inline.hpp"
#include "humandyn/model.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <type_traits>

namespace humandyn::detail {

// Calls f(i, twist, mounted, massless) for every joint, parents before children. `twist` is an
// integral_constant<Twist, ...>; i, mounted and massless are integral_constants for a static shape
// and plain int / bool otherwise.
template <class Model, class F>
inline void for_each_joint(const Model& model, F&& f) {
  using Shape = typename Model::shape_type;
  if constexpr (Shape::is_static) {
    (void)model;
    static_for<Shape::nj>([&](auto I) {
      constexpr auto i = std::size_t(decltype(I)::value);
      f(I, std::integral_constant<Twist, Shape::spec.twist[i]>{}, std::bool_constant<Shape::spec.mounted[i]>{},
        std::bool_constant<Shape::spec.massless[i]>{});
    });
  } else {
    for (int i = 0; i < model.size(); ++i) {
      const auto& c = model.joint(i);
      with_twist(c.twist, [&](auto T) { f(i, T, c.mounted, c.mass == 0); });
    }
  }
}

// As for_each_joint, children before parents.
template <class Model, class F>
inline void for_each_joint_reverse(const Model& model, F&& f) {
  using Shape = typename Model::shape_type;
  if constexpr (Shape::is_static) {
    (void)model;
    static_for_reverse<Shape::nj>([&](auto I) {
      constexpr auto i = std::size_t(decltype(I)::value);
      f(I, std::integral_constant<Twist, Shape::spec.twist[i]>{}, std::bool_constant<Shape::spec.mounted[i]>{},
        std::bool_constant<Shape::spec.massless[i]>{});
    });
  } else {
    for (int i = model.size() - 1; i >= 0; --i) {
      const auto& c = model.joint(i);
      with_twist(c.twist, [&](auto T) { f(i, T, c.mounted, c.mass == 0); });
    }
  }
}

// The cosines and sines of every joint's theta_i + q_i into cos_q[i] and sin_q[i], in a sweep of their
// own before the pass that reads them: each is independent of the others, so the processor overlaps
// them, where computed inside the pass's steps each would wait for the step before it (full inverse
// dynamics took 5-26 % less time, docs/performance.md). The sweep is out of line and flattened
// (call_flattened), so that cos_sin is inline in it wherever it is called from. A float body computes
// them a register's lanes at a time (4 floats with SSE2, 16 with AVX-512), each with the bits it has
// alone (sin_cos_float).
template <class Model, class Q, class Out>
inline void joint_cos_sin(const Model& model, const Eigen::MatrixBase<Q>& q, Out& cos_q, Out& sin_q) noexcept {
  using S = typename Model::scalar_type;
  const auto sweep = [&] {
    if constexpr (std::is_same_v<S, float>) {
      using B = stdx::native_simd<float>;
      constexpr int W = int(B::size());
      const int n = model.size();
      for (int i0 = 0; i0 < n; i0 += W) {
        const B angle([&](auto l) {
          const int i = i0 + int(l);
          return i < n ? float(model.joint(i).theta + float(q[i])) : 0.0f;
        });
        B c, s;
        cos_sin(angle, c, s);
        for (int l = 0; l < W && i0 + l < n; ++l) {
          cos_q[std::size_t(i0 + l)] = c[std::size_t(l)];
          sin_q[std::size_t(i0 + l)] = s[std::size_t(l)];
        }
      }
    } else {
      for_each_joint(model, [&](auto i, auto, auto, auto) {
        const auto k = std::size_t(i);
        cos_sin(S(model.joint(int(i)).theta + S(q[int(i)])), cos_q[k], sin_q[k]);
      });
    }
  };
  call_flattened(sweep);
}

// Calls f(twist, mounted) for the single joint a (an integral_constant or an int, as for_each_ancestor
// hands them out): compile-time facts for a static shape and a constant a, runtime ones otherwise.
template <class Model, class I, class F>
inline void with_joint(const Model& model, I a, F&& f) {
  using Shape = typename Model::shape_type;
  if constexpr (Shape::is_static && !std::is_same_v<I, int>) {
    (void)model;
    constexpr auto k = std::size_t(I::value);
    f(std::integral_constant<Twist, Shape::spec.twist[k]>{}, std::bool_constant<Shape::spec.mounted[k]>{});
  } else {
    const auto& c = model.joint(int(a));
    with_twist(c.twist, [&](auto T) { f(T, c.mounted); });
  }
}

}  // namespace humandyn::detail
