// The shape of a model: which joint hangs from which, and what is known about each joint before
// any length or mass is (a body's static shape is derived from its table, body.hpp). A shape known when compiling lets
// the algorithms unroll their loops and turn the DH twists of 0, ±90° and 180° into sign swaps; a runtime shape
// (DynamicShape) runs the same code through a loop.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <stdexcept>

namespace humandyn {

/// A DH twist alpha that the algorithms specialise: Rx(alpha) is then a permutation with signs.
/// Zero, HalfPi, MinusHalfPi, Pi: alpha = 0, +90°, -90°, 180°; General: any other angle, Rx(alpha) from its
/// cosine and sine.
enum class Twist : std::uint8_t { Zero, HalfPi, MinusHalfPi, Pi, General };

/// The twist class of an angle, within `tol` of the special values. An angle stored in
/// float is only within its rounding of them (90 degrees is 4e-8 off), so models pass a tolerance
/// that follows their scalar type (Model::twist_tolerance).
/// \param alpha  DH twist (rad), any multiple of 2 pi away
/// \param tol    how far from a special value still counts as it (rad)
/// \return the class; Twist::General if no special value is within `tol`
inline Twist classify_twist(double alpha, double tol = 1e-12) noexcept {
  constexpr double pi = 3.14159265358979323846;
  double a = std::remainder(alpha, 2.0 * pi);  // in [-pi, pi]
  if (std::abs(a) <= tol) return Twist::Zero;
  if (std::abs(a - pi / 2) <= tol) return Twist::HalfPi;
  if (std::abs(a + pi / 2) <= tol) return Twist::MinusHalfPi;
  if (std::abs(std::abs(a) - pi) <= tol) return Twist::Pi;
  return Twist::General;
}

/// A serial chain: `length` consecutive joints starting at `first`, hanging from joint `parent`'s
/// link (-1: the base). The parent link is the branch point where the chain's forces and moments are
/// summed with those of its siblings (the seed's eq. 9 and 11).
struct ChainSpec {
  int first = 0;    ///< index of the chain's first joint (0-based)
  int length = 0;   ///< number of joints in the chain
  int parent = -1;  ///< joint whose link the chain hangs from; -1: the base
};

/// Per-joint facts fixed at compile time. Joints are numbered so that every parent comes before its
/// children (topological order), chain after chain.
template <int N>
struct ShapeSpec {
  std::array<int, N> parent{};     ///< parent joint, -1 for the base
  std::array<Twist, N> twist{};    ///< DH twist class of each link
  std::array<bool, N> mounted{};   ///< a fixed mount transform sits between parent link and joint
  std::array<bool, N> massless{};  ///< the link carries no mass (its inertial terms are skipped)
};

/// A set of joints of an N-joint shape (0-based), N <= 64, kept as one bit mask: a structural type whose
/// value is its members alone, so that two scenes (SceneSpec, scene.hpp) that hold different joints are
/// different types however their sets were built. (GCC 12 takes two std::array<bool, N> template arguments
/// filled in element by element after a zero start, say {1, 0, 0} and {0, 0, 1}, for one value.)
template <int N>
struct JointSet {
  static_assert(0 <= N && N <= 64, "a JointSet holds up to 64 joints");
  std::uint64_t bits = 0;  ///< bit i: joint i is in the set

  constexpr JointSet() = default;
  /// The listed joints (0-based, each in [0, N), each once; another list is an error, at compile time in a
  /// constant: N flags written as 0s and 1s, which would read as joints 0 and 1, repeat one).
  constexpr JointSet(std::initializer_list<int> joints) {
    for (const int j : joints) {
      if (j >= 0 && j < N && (*this)[std::size_t(j)])
        throw std::invalid_argument("JointSet: a joint listed twice (N flags go in a std::array<bool, N>)");
      set(j);  // (its range checked there)
    }
  }
  /// (A list of flags is no list of joints: N flags go in a std::array<bool, N>.)
  JointSet(std::initializer_list<bool>) = delete;
  /// The joints whose flag is true (N flags).
  constexpr JointSet(const std::array<bool, std::size_t(N)>& flags) {  // NOLINT(google-explicit-constructor)
    for (int i = 0; i < N; ++i)
      if (flags[std::size_t(i)]) set(i);
  }
  /// Every joint of the shape.
  static constexpr JointSet all() {
    JointSet s;
    for (int i = 0; i < N; ++i) s.set(i);
    return s;
  }

  /// Whether joint i is in the set.
  constexpr bool operator[](std::size_t i) const noexcept { return (bits >> i) & 1U; }
  /// Puts joint i in the set (or takes it out); a joint outside [0, N) is an error (at compile time in a
  /// constant).
  constexpr void set(int i, bool in = true) {
    if (i < 0 || i >= N) throw std::out_of_range("JointSet: a joint index outside [0, N)");
    const std::uint64_t bit = std::uint64_t(1) << i;
    bits = in ? bits | bit : bits & ~bit;
  }
  /// Whether the set holds no joint.
  constexpr bool empty() const noexcept { return bits == 0; }
  /// The set as N flags.
  constexpr std::array<bool, std::size_t(N)> flags() const noexcept {
    std::array<bool, std::size_t(N)> out{};
    for (int i = 0; i < N; ++i) out[std::size_t(i)] = (*this)[std::size_t(i)];
    return out;
  }
  friend constexpr bool operator==(const JointSet&, const JointSet&) = default;
};

/// Counts the chains of a parent array: a chain starts at the base, after a branch point, or where a
/// joint does not follow its predecessor.
/// \param parent  each joint's parent (-1: the base), parents before children
/// \param n       number of joints
/// \return the number of chains (the size split_chains needs)
template <class ParentArray>
constexpr int count_chains(const ParentArray& parent, int n) {
  const auto parent_of = [&parent](int i) { return parent[static_cast<std::size_t>(i)]; };
  int chains = 0;
  for (int i = 0; i < n; ++i) {
    int children_of_parent = 0;
    for (int j = 0; j < n; ++j) children_of_parent += (parent_of(j) == parent_of(i)) ? 1 : 0;
    const bool starts = (i == 0) || parent_of(i) != i - 1 || children_of_parent > 1;
    chains += starts ? 1 : 0;
  }
  return chains;
}

/// Splits a parent array into serial chains (see count_chains).
/// \param parent  each joint's parent (-1: the base), parents before children
/// \param n       number of joints
/// \param out     receives the chains in joint order; must hold count_chains(parent, n) entries
template <class ParentArray, class ChainArray>
constexpr void split_chains(const ParentArray& parent, int n, ChainArray& out) {
  const auto parent_of = [&parent](int i) { return parent[static_cast<std::size_t>(i)]; };
  std::size_t c = 0;  // (one past the chain being filled)
  for (int i = 0; i < n; ++i) {
    int children_of_parent = 0;
    for (int j = 0; j < n; ++j) children_of_parent += (parent_of(j) == parent_of(i)) ? 1 : 0;
    const bool starts = (i == 0) || parent_of(i) != i - 1 || children_of_parent > 1;
    if (starts) out[c++] = ChainSpec{i, 0, parent_of(i)};
    ++out[c - 1].length;
  }
}

/// A shape known only at run time (an imported model): the same algorithms run as a loop.
struct DynamicShape {
  static constexpr int nj = Eigen::Dynamic;  ///< the number of joints is the model's (Model::size())
  static constexpr bool is_static = false;   ///< the algorithms run as a loop, not unrolled
};

}  // namespace humandyn
