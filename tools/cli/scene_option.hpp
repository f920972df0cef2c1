// `--scene NAME` for the subcommands that compute dynamics (id, fd, simulate): one of the named scenes of
// humandyn/scene.hpp on the seed body, run on full-size joint vectors in the model's joint order, so a
// subcommand reads and writes the same columns whatever the scene (only fewer of them).
#pragma once

#include "cli/errors.hpp"
#include "cli/joint_table.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/integrators.hpp"
#include "humandyn/model.hpp"
#include "humandyn/servo.hpp"

#include <CLI/CLI.hpp>
#include <Eigen/Core>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace humandyn::cli {

// A named scene built on a seed-shaped body.
class SceneRunner {
 public:
  // `name`: a named scene (UsageError listing them if unknown); `description`: a body of the seed's shape
  // (UsageError otherwise); the scene's locked joints are held at q_lock (full size, radians).
  SceneRunner(const std::string& name, const ModelDescription<double>& description, const Eigen::VectorXd& q_lock);

  const std::string& name() const;
  Terms terms() const;                         // the terms of its inverse dynamics
  bool output(int joint) const;                // whether its inverse dynamics computes this joint's torque
  bool locked(int joint) const;                // whether the joint is held at its lock angle
  const Eigen::VectorXd& lock_angles() const;  // the angles the locked joints are held at (full size)

  // Joint torques for a full-size state: zero where not an output. Locked joints' rates and
  // accelerations are taken as zero (their angles as the lock angles).
  Eigen::VectorXd inverse_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd);

  // Joint accelerations for full-size angles, rates and torques: zero at locked joints, whose torques
  // are not read. The scene's terms, except that a gravity-only scene keeps its inertia (forward_terms).
  Eigen::VectorXd forward_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& tau,
                                   FdMethod method = FdMethod::Articulated);

  // The pivots of the last forward dynamics (articulated: the articulated inertia about each joint axis;
  // mass matrix: D of M = L^T D L), full size; locked joints carry the largest pivot.
  Eigen::VectorXd pivots(FdMethod method) const;

  // Whether the scene's forward dynamics uses the velocity products (its rate columns are needed).
  bool forward_uses_rates() const;

  // One time step (scene_step) from the full-size state (q, qd), overwritten on success: the locked
  // joints are held at their lock angles with zero rate, the torques and the servo (full size, may be
  // null) are restricted to the scene's joints. ImplicitPD always uses the mass matrix. The status's
  // joint is a full joint index.
  StepStatus step(Integrator integrator, FdMethod method, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                  const Eigen::VectorXd& tau, const PdServo<AnyModel<double>>* servo, double h);

 private:
  struct Impl;
  std::shared_ptr<Impl> impl_;
};

// `--scene NAME [--lock JOINT=ANGLE[,JOINT=ANGLE...]]`: a named scene, and the angles (rad) at which it holds
// some of its locked joints (make_scene applies them).
struct SceneOptions {
  std::string scene;  // "" for none
  std::string lock;
};

// Registers --scene (`scene_help` followed by one line per named scene, saying what it drops; a usage error
// naming the choices when unknown) and --lock (`lock_help`; it needs --scene). Returns --scene.
CLI::Option* add_scene_options(CLI::App& command, SceneOptions& options, const std::string& scene_help,
                               const std::string& lock_help);

// The scene `options.scene` (none if "") on `description`, its locked joints held at q_start's angles except
// those `options.lock` sets. UsageError naming the JOINT=ANGLE pair if the joint is not in the
// model, is not locked by the scene, is given twice, or the angle is not a finite number.
std::optional<SceneRunner> make_scene(const SceneOptions& options, const ModelDescription<double>& description,
                                      const Eigen::VectorXd& q_start);

// Says on stderr ("humandyn <command>: warning: ..."), once per column, what the scene leaves unread of
// `csv` (the states of id and fd, the track of simulate) that would have moved a locked joint: an angle
// other than the one it is held at, a rate or an acceleration other than 0 (the first such row named).
// Nothing is changed.
void warn_locked_motion(const SceneRunner& scene, const CsvTable& csv, const std::vector<std::string>& joint_names,
                        const std::string& command);

// The terms of the named scene `name` (which --scene accepted).
Terms scene_terms(const std::string& name);

// The joints whose columns a command reads under `options`: without --scene, every joint. With one, a
// locked joint is held still, so its rate, acceleration and torque columns are not read (and may be left
// out), and its angle column only when --lock does not give its angle (the first row's is its lock angle).
struct SceneJoints {
  std::vector<std::size_t> moving;  // the joints whose rates, accelerations and torques are read
  std::vector<std::size_t> angles;  // the joints whose angles are read
};
SceneJoints scene_joints(const SceneOptions& options, const ModelDescription<double>& description);

// The columns `<prefix><joint>` as two groups: those of the joints `read`, with `use`; the others, Ignored.
std::array<ColumnGroup, 2> joint_column_groups(const std::vector<std::string>& joint_names, std::string_view prefix,
                                               const std::vector<std::size_t>& read, ColumnGroup::Use use);

}  // namespace humandyn::cli
