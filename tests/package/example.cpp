// The README's example, built against the installed package by the package_consumer test.
#include <humandyn/humandyn.hpp>

#include <cstdio>

int main() {
  using namespace humandyn;
  using Body = HumanModel<double>;
  const Body model = default_model();  // de Leva's reference male: 16 joints in five DH chains
  Data<Body> data(model);              // one workspace per character (or thread)

  Body::JointVector q = Body::JointVector::Zero(), qd = q, qdd = q;
  q[model.joint_index("l_shoulder_pitch")] = -1.5707963267948966;  // left arm raised forward
  qdd[model.joint_index("l_elbow_pitch")] = 2.0;                   // the elbow speeding up

  const Body::JointVector tau = rnea(model, data, q, qd, qdd);               // Newton-Euler torques (N m)
  const Body::JointVector hold = gravity_torques(model, data, q);            // what holds the pose still
  const Body::JointVector back = forward_dynamics(model, data, q, qd, tau);  // back to qdd

  State<Body> state(model);  // one 1 ms RK4 step, holding the pose
  StepWorkspace<Body> ws(model);
  state.q = q;
  const StepStatus status = step<Integrator::RungeKutta4>(model, ws, state, hold, 1e-3);
  std::printf("shoulder %.3f N m, qdd error %.1e, step: %s\n", tau[6], (back - qdd).norm(),
              describe(status, model).c_str());
  return status.ok() && (back - qdd).norm() < 1e-9 ? 0 : 1;
}
