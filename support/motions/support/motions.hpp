// The states the benchmarks run on: a pool of random states, and two realistic motions built from smooth
// joint trajectories whose velocities and accelerations are exact derivatives (never finite differences).
//   random_states   |q| <= 1 rad, |qd| <= 2 rad/s, |qdd| <= 5 rad/s^2, uniform, fixed seed
//   walking_cycle   one 1.1 s gait cycle over the right (stance) foot: the body rolls over the ankle, the left
//                   leg swings, the arms swing against the legs, the waist twists (sums of sines)
//   arm_raise       the left arm raised forward from hanging to horizontal in 1.2 s, minimum-jerk profile
// Angles follow the seed's joint frames: a pitch joint turns about the lateral axis, so a positive angle
// tilts what is above the joint forward and swings what hangs below it backward.
#pragma once

#include "humandyn/body.hpp"
#include "support/random_states.hpp"

#include <Eigen/Core>

#include <cmath>
#include <string>
#include <vector>

namespace humandyn::bench {

// One sampled motion (or pool): q, qd and qdd per sample, in double. Every variant reads the same samples.
struct StateSet {
  std::string name;
  std::vector<Eigen::VectorXd> q, qd, qdd;
  int size() const { return int(q.size()); }
};

// Uniform random states in the ranges above, from a fixed seed (reproducible between runs).
inline StateSet random_states(int nj, int count, unsigned seed = 20260521u) {
  StateSet s{"random", {}, {}, {}};
  for (auto& x : support::random_states(nj, count, seed, 1.0, 2.0, 5.0)) {
    s.q.push_back(std::move(x.q));
    s.qd.push_back(std::move(x.qd));
    s.qdd.push_back(std::move(x.qdd));
  }
  return s;
}

// q_j(t) = offset + amplitude * sin(multiple * omega * t + phase), summed over the terms of joint j.
struct Harmonic {
  int joint;
  double offset, amplitude;
  int multiple;
  double phase;
};

// q, qd and qdd of sum-of-sines trajectories at time t, in any scalar type (long double for references).
template <class S, class Vector>
void evaluate_harmonics(const std::vector<Harmonic>& terms, double period, S t, Vector& q, Vector& qd, Vector& qdd) {
  const S omega = S(2) * S(3.14159265358979323846264338327950288L) / S(period);
  q.setZero();
  qd.setZero();
  qdd.setZero();
  for (const auto& h : terms) {
    using std::cos;
    using std::sin;
    const S w = S(h.multiple) * omega, arg = w * t + S(h.phase), a = S(h.amplitude);
    q[h.joint] += S(h.offset) + a * sin(arg);
    qd[h.joint] += a * w * cos(arg);
    qdd[h.joint] += -a * w * w * sin(arg);
  }
}

// Samples sum-of-sines trajectories with exact derivatives at `count` instants over one period.
inline StateSet sample_harmonics(const std::string& name, int nj, const std::vector<Harmonic>& terms, double period,
                                 int count) {
  StateSet s{name, {}, {}, {}};
  for (int i = 0; i < count; ++i) {
    const double t = period * double(i) / double(count);
    Eigen::VectorXd q(nj), qd(nj), qdd(nj);
    evaluate_harmonics(terms, period, t, q, qd, qdd);
    s.q.push_back(q);
    s.qd.push_back(qd);
    s.qdd.push_back(qdd);
  }
  return s;
}

// Joint indices of the seed body, looked up in its table by name.
namespace seed_joint {
inline constexpr int r_ankle_pitch = seed_body.index("r_ankle_pitch");
inline constexpr int r_knee_pitch = seed_body.index("r_knee_pitch");
inline constexpr int r_hip_roll = seed_body.index("r_hip_roll");
inline constexpr int r_hip_pitch = seed_body.index("r_hip_pitch");
inline constexpr int waist_pitch = seed_body.index("waist_pitch");
inline constexpr int waist_yaw = seed_body.index("waist_yaw");
inline constexpr int l_shoulder_pitch = seed_body.index("l_shoulder_pitch");
inline constexpr int l_shoulder_roll = seed_body.index("l_shoulder_roll");
inline constexpr int l_elbow_pitch = seed_body.index("l_elbow_pitch");
inline constexpr int r_shoulder_pitch = seed_body.index("r_shoulder_pitch");
inline constexpr int r_shoulder_roll = seed_body.index("r_shoulder_roll");
inline constexpr int r_elbow_pitch = seed_body.index("r_elbow_pitch");
inline constexpr int l_hip_pitch = seed_body.index("l_hip_pitch");
inline constexpr int l_hip_roll = seed_body.index("l_hip_roll");
inline constexpr int l_knee_pitch = seed_body.index("l_knee_pitch");
inline constexpr int l_ankle_pitch = seed_body.index("l_ankle_pitch");
}  // namespace seed_joint

// A walking-like cycle of the 16-joint seed body (period 1.1 s; peak joint speeds 0.3-6.3 rad/s and
// accelerations up to 72 rad/s^2 at the swinging knee, the range of human gait): the stance ankle rolls
// the body over the foot (±0.2 rad), the stance knee flexes twice per cycle, the stance hip pitch cancels
// both so the trunk stays upright; the hips sway (±0.05 rad roll); the free leg swings at the hip
// (±0.45 rad) and flexes at the knee (0 to 1.1 rad); the arms swing against the legs (±0.35 rad) with
// bent elbows; the waist twists (±0.1 rad) and nods (±0.05 rad).
inline const std::vector<Harmonic>& walking_terms() {
  using namespace seed_joint;
  constexpr double half_pi = 1.57079632679489661923;
  static const std::vector<Harmonic> terms{
      // stance leg
      {r_ankle_pitch, 0, 0.20, 1, -half_pi},
      {r_knee_pitch, -0.10, 0.10, 2, half_pi},  // -0.1 + 0.1 cos(2wt): 0 to -0.2 (flexion)
      {r_hip_pitch, 0, -0.20, 1, -half_pi},     // minus the ankle and knee: the trunk stays upright
      {r_hip_pitch, 0.10, -0.10, 2, half_pi},
      {r_hip_roll, 0, 0.05, 1, 0},
      // waist
      {waist_pitch, 0, 0.05, 2, 0},
      {waist_yaw, 0, 0.10, 1, 0},
      // arms against the legs, elbows bent
      {l_shoulder_pitch, 0, 0.35, 1, 0},
      {l_shoulder_roll, -0.10, 0.03, 2, 0},
      {l_elbow_pitch, -0.30, 0.15, 1, 0},
      {r_shoulder_pitch, 0, -0.35, 1, 0},
      {r_shoulder_roll, 0.10, -0.03, 2, 0},
      {r_elbow_pitch, -0.30, -0.15, 1, 0},
      // free leg: hip flexion swings it forward (negative), knee flexion folds the shank back (positive)
      {l_hip_pitch, 0, -0.45, 1, 0},
      {l_hip_roll, 0, 0.05, 1, 0},
      {l_knee_pitch, 0.55, 0.55, 2, -half_pi},  // 0.55 - 0.55 cos(2wt): 0 to 1.1
      {l_ankle_pitch, 0, 0.15, 1, 0.5},
  };
  return terms;
}

inline constexpr double walking_period = 1.1;  // s

inline StateSet walking_cycle(int count) {
  return sample_harmonics("walking", seed_body.size, walking_terms(), walking_period, count);
}

// The left arm raised forward from hanging (0) to horizontal (-pi/2 at the shoulder pitch) in 1.2 s on a
// minimum-jerk profile s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5 (peak 2.5 rad/s, 6.3 rad/s^2), the elbow
// bending to 0.3 rad and the arm opening by 0.1 rad on the same profile; the rest of the body stands still.
inline StateSet arm_raise(int count) {
  using namespace seed_joint;
  constexpr double duration = 1.2;
  struct Move {
    int joint;
    double to;
  };
  const Move moves[] = {{l_shoulder_pitch, -1.57079632679489661923}, {l_elbow_pitch, -0.3}, {l_shoulder_roll, -0.1}};
  StateSet s{"arm raise", {}, {}, {}};
  for (int i = 0; i < count; ++i) {
    const double tau = double(i) / double(count - 1);
    const double p = tau * tau * tau * (10 - 15 * tau + 6 * tau * tau);
    const double dp = 30 * tau * tau * (1 - 2 * tau + tau * tau) / duration;
    const double ddp = 60 * tau * (1 - 3 * tau + 2 * tau * tau) / (duration * duration);
    Eigen::VectorXd q = Eigen::VectorXd::Zero(seed_body.size), qd = q, qdd = q;
    for (const auto& m : moves) {
      q[m.joint] = m.to * p;
      qd[m.joint] = m.to * dp;
      qdd[m.joint] = m.to * ddp;
    }
    s.q.push_back(q);
    s.qd.push_back(qd);
    s.qdd.push_back(qdd);
  }
  return s;
}

// Both realistic motions, one after the other (the "motions" workload of the error tables).
inline StateSet realistic_motions(int count_each) {
  StateSet s = walking_cycle(count_each);
  const StateSet a = arm_raise(count_each);
  s.name = "motions";
  s.q.insert(s.q.end(), a.q.begin(), a.q.end());
  s.qd.insert(s.qd.end(), a.qd.begin(), a.qd.end());
  s.qdd.insert(s.qdd.end(), a.qdd.begin(), a.qdd.end());
  return s;
}

}  // namespace humandyn::bench
