// Simulation scenarios for the work-precision measurement and the 1 kHz simulation loop:
//   tracked walk    a PD servo (4 Hz bandwidth, critically damped, gains scaled by each joint's inertia)
//                   with inverse-dynamics feed-forward tracks the walking cycle for one period (1.1 s);
//                   reference and feed-forward are continuous functions of time, evaluated at each stage
//                   (a torque schedule, integrators.hpp), so that the exact motion is the walking cycle
//                   itself whatever the step, and the error measures the integrator alone;
//   passive swing   the servo, with the start pose's gravity torques as feed-forward, holds the stance leg,
//                   the waist and the roll joints; the pitch joints of both
//                   arms and of the free leg start displaced (left arm 34° forward, right arm 23° back, free
//                   leg 23° forward, knee bent 11°) and swing under gravity alone, undamped, for 1 s.
// A scenario runs in any scalar type: long double with a fine RK4 step gives the reference end state.
#pragma once

#include "bench/timing.hpp"
#include "bench/work_precision.hpp"
#include "humandyn/algorithm/crba.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/integrators.hpp"
#include "humandyn/servo.hpp"
#include "support/motions.hpp"

#include <Eigen/Core>

#include <cmath>
#include <string>
#include <vector>

namespace humandyn::bench {

enum class Scenario { TrackedWalk, PassiveSwing };

inline const char* scenario_name(Scenario s) { return s == Scenario::TrackedWalk ? "tracked walk" : "passive swing"; }

inline double scenario_duration(Scenario s) { return s == Scenario::TrackedWalk ? walking_period : 1.0; }

// Servo gains for a bandwidth of `hz`, per joint from the mass matrix at the home pose: the stiffness
// from the inertia the joint moves when the others are held, kp = w^2 M_ii; the damping critical for the
// inertia it moves when the others are free, kd = 2 sqrt(kp / (M^-1)_ii). (The hip pitches and the waist
// pitch turn about one line with the light pelvis between them: that combination has little inertia, and
// damping scaled by M_ii would make it needlessly stiff.)
template <class Model>
void set_servo_gains(const Model& model, PdServo<Model>& servo, double hz) {
  using S = typename Model::scalar_type;
  Data<Model> data(model);
  typename Model::JointVector q;
  q.setZero(model.size());
  crba(model, data, q);
  const Eigen::MatrixXd M = data.M.template cast<double>().template selfadjointView<Eigen::Lower>();
  const Eigen::VectorXd m_inv = M.inverse().diagonal();
  const double w = 2 * 3.14159265358979323846 * hz;
  for (int i = 0; i < model.size(); ++i) {
    const double kp = w * w * M(i, i);
    servo.kp[i] = S(kp);
    servo.kd[i] = S(2 * std::sqrt(kp / m_inv[i]));
  }
}

// The start of the passive swing.
template <class Vector>
void passive_swing_start(Vector& q) {
  using S = typename Vector::Scalar;
  using namespace seed_joint;
  q.setZero();
  q[l_shoulder_pitch] = S(-0.6);
  q[r_shoulder_pitch] = S(0.4);
  q[l_hip_pitch] = S(-0.4);
  q[l_knee_pitch] = S(0.2);
}

// The joints that swing freely in the passive swing: the pitch joints of both arms and of the free leg
// (shoulders, elbows, hip, knee, ankle); the roll joints stay held with the stance leg and the waist.
inline bool swings_freely(int joint) {
  using namespace seed_joint;
  switch (joint) {
    case l_shoulder_pitch:
    case l_elbow_pitch:
    case r_shoulder_pitch:
    case r_elbow_pitch:
    case l_hip_pitch:
    case l_knee_pitch:
    case l_ankle_pitch:
      return true;
    default:
      return false;
  }
}

// One simulation of a scenario with a fixed step: the end state, whether every step succeeded, and the
// model, workspace and servo it ran with (reused between runs).
template <class Model>
class ScenarioRun {
 public:
  using S = typename Model::scalar_type;
  using V = typename Model::JointVector;

  ScenarioRun(const Model& model, Scenario scenario)
      : model_(model), scenario_(scenario), ws_(model), x_(model), servo_(model), data_(model) {
    set_servo_gains(model, servo_, 4.0);
    if (scenario == Scenario::PassiveSwing)
      for (int i = 0; i < model.size(); ++i)
        if (swings_freely(i)) servo_.kp[i] = servo_.kd[i] = S(0);
    q_ref_.setZero(model.size());
    qd_ref_.setZero(model.size());
    qdd_ref_.setZero(model.size());
    tau_.setZero(model.size());
  }

  // Runs `steps` steps of T / steps; false when a step failed (non-finite or runaway state).
  template <Integrator integrator, FdMethod method = FdMethod::MassMatrix>
  bool run(int steps) {
    const S T = S(scenario_duration(scenario_));
    const S h = T / S(steps);
    // start on the reference (tracked walk) or at rest in the displaced pose (passive swing)
    if (scenario_ == Scenario::TrackedWalk) {
      evaluate_harmonics(walking_terms(), walking_period, S(0), q_ref_, qd_ref_, qdd_ref_);
      x_.q = q_ref_;
      x_.qd = qd_ref_;
    } else {
      passive_swing_start(x_.q);
      x_.qd.setZero();
      servo_.q_ref = x_.q;
      servo_.qd_ref.setZero();
      // the held joints get the static torques of the start pose (gravity compensation), the free ones none
      tau_ = gravity_torques(model_, data_, x_.q);
      for (int i = 0; i < model_.size(); ++i)
        if (swings_freely(i)) tau_[i] = S(0);
    }
    if (scenario_ == Scenario::TrackedWalk) {
      // the servo's law Kp (q_ref - q) + Kd (qd_ref - qd) split: its reference part joins the feed-forward in
      // the schedule, at the stage's own time t + s; the servo keeps -Kp q - Kd qd (implicit where the step is)
      servo_.q_ref.setZero();
      servo_.qd_ref.setZero();
      for (int k = 0; k < steps; ++k) {
        const S t = S(k) * h;
        const auto schedule = [this, t](S s, V& tau) noexcept {
          evaluate_harmonics(walking_terms(), walking_period, t + s, q_ref_, qd_ref_, qdd_ref_);
          tau = rnea(model_, data_, q_ref_, qd_ref_, qdd_ref_);
          tau += servo_.kp.cwiseProduct(q_ref_) + servo_.kd.cwiseProduct(qd_ref_);
        };
        last_ = step<integrator, method>(model_, ws_, x_, schedule, &servo_, h);
        if (!last_.ok()) return false;
      }
      return true;
    }
    for (int k = 0; k < steps; ++k) {
      last_ = step<integrator, method>(model_, ws_, x_, tau_, &servo_, h);
      if (!last_.ok()) return false;
    }
    return true;
  }

  const State<Model>& state() const { return x_; }
  const StepStatus& last_status() const { return last_; }

 private:
  const Model& model_;
  Scenario scenario_;
  StepWorkspace<Model> ws_;
  State<Model> x_;
  PdServo<Model> servo_;
  Data<Model> data_;
  V q_ref_, qd_ref_, qdd_ref_, tau_;
  StepStatus last_;
};

}  // namespace humandyn::bench
