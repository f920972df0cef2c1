// HUMANDYN_FLATTEN: everything the function calls inlined into it, for such an out-of-line step.
// HUMANDYN_NOINLINE: for a per-joint step that is better called than copied into each of the joints
// (one copy per twist class instead of one per joint: the code then shrinks with the work a scene keeps).
// HUMANDYN_ALWAYS_INLINE: for the small helpers called inside the loops that a static shape unrolls into
// one long function, where the compiler would otherwise stop inlining them and pay a call (and a trip
// through memory) per joint.
// HUMANDYN_FLATTEN: for a per-joint step whose many small vector operations (Eigen's) must all be inlined
// into it, which the compiler stops doing in a large translation unit.
#pragma once

// Defining HUMANDYN_NO_FORCED_INLINE leaves all three to the compiler: the code means the same, and a debug or
// sanitizer build of the unrolled passes compiles several times faster.
#if defined(HUMANDYN_NO_FORCED_INLINE)
#define HUMANDYN_ALWAYS_INLINE inline
#elif defined(__GNUC__) || defined(__clang__)
#define HUMANDYN_ALWAYS_INLINE inline __attribute__((always_inline))
#elif defined(_MSC_VER)
#define HUMANDYN_ALWAYS_INLINE __forceinline
#else
#define HUMANDYN_ALWAYS_INLINE inline
#endif

#if defined(HUMANDYN_NO_FORCED_INLINE)
#define HUMANDYN_NOINLINE
#elif defined(__GNUC__) || defined(__clang__)
#define HUMANDYN_NOINLINE __attribute__((noinline))
#elif defined(_MSC_VER)
#define HUMANDYN_NOINLINE __declspec(noinline)
#else
#define HUMANDYN_NOINLINE
#endif

#if defined(HUMANDYN_NO_FORCED_INLINE) || !(defined(__GNUC__) || defined(__clang__))
#define HUMANDYN_FLATTEN
#else
#define HUMANDYN_FLATTEN __attribute__((flatten))
#endif

namespace humandyn::detail {

// f() out of line, with everything f calls inlined into it: for a pass over a batch of lanes, where the
// compiler would call the small functions in it and pass their results through memory.
template <class F>
HUMANDYN_NOINLINE HUMANDYN_FLATTEN inline void call_flattened(const F& f) noexcept {
  f();
}

}  // namespace humandyn::detail
