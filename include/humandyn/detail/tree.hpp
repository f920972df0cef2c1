// Walks up the tree: a joint's parent and its chain of ancestors, as compile-time constants for a
// static shape (so the walks unroll) and through the model's parent array otherwise.
#pragma once

#include "humandyn/detail/inline.hpp"

#include <type_traits>

namespace humandyn::detail {

// The parent of joint i (-1 for the base).
template <class Model, class I>
inline constexpr int parent_of(const Model& model, I i) noexcept {
  using Shape = typename Model::shape_type;
  if constexpr (Shape::is_static) {
    (void)model;
    return Shape::spec.parent[std::size_t(int(i))];
  } else {
    return model.joint(int(i)).parent;
  }
}

// Calls f(a) for every proper ancestor a of joint i, nearest first: an integral_constant for a static
// shape when i is one, a plain int otherwise.
template <class Model, class I, class F>
inline void for_each_ancestor(const Model& model, I i, F&& f) {
  using Shape = typename Model::shape_type;
  if constexpr (Shape::is_static && !std::is_same_v<I, int>) {
    constexpr int p = Shape::spec.parent[std::size_t(I::value)];
    if constexpr (p >= 0) {
      f(std::integral_constant<int, p>{});
      for_each_ancestor(model, std::integral_constant<int, p>{}, f);
    }
  } else {
    for (int a = parent_of(model, int(i)); a >= 0; a = parent_of(model, a)) f(a);
  }
}

// As for_each_ancestor, with every step of a static shape's walk forced inline: for the walks inside a
// long unrolled pass, where the compiler would otherwise stop inlining and call each step.
template <class Model, class I, class F>
HUMANDYN_ALWAYS_INLINE void for_each_ancestor_inline(const Model& model, I i, F&& f) {
  using Shape = typename Model::shape_type;
  if constexpr (Shape::is_static && !std::is_same_v<I, int>) {
    constexpr int p = Shape::spec.parent[std::size_t(I::value)];
    if constexpr (p >= 0) {
      f(std::integral_constant<int, p>{});
      for_each_ancestor_inline(model, std::integral_constant<int, p>{}, f);
    }
  } else {
    for_each_ancestor(model, i, f);
  }
}

}  // namespace humandyn::detail
