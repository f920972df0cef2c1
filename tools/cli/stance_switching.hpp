// The right- and left-stance models of one body, for the commands whose rows switch the stance foot (a
// `stance` column): a left row's state is the right-stance model's, carried to the left-stance model by
// the exact state map (stance.hpp) and its results carried back.
#pragma once

#include "cli/joint_table.hpp"
#include "humandyn/data.hpp"
#include "humandyn/model.hpp"
#include "humandyn/stance.hpp"

#include <array>
#include <string>

namespace humandyn::cli {

class StanceSwitching {
 public:
  using M = AnyModel<double>;

  // Throws UsageError naming `file` (the states' file) and `model` when the body is not of the seed's shape
  // or its sides are not mirror images (the left-stance model is its mirror image).
  StanceSwitching(const ModelDescription<double>& right, const std::string& file, const std::string& model);

  const M& left() const { return left_any_; }
  Data<M>& left_data() { return left_ws_; }

  // The left model's angles and rates for the right model's (q, qd); returns the left model's base pose,
  // its foot at rest where the right model puts it.
  Pose<double> to_left(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Eigen::VectorXd& lq,
                       Eigen::VectorXd& lqd) const;

  // A joint-space vector (rates, accelerations, torques) carried across: a joint's entry keeps its number
  // up to the sign its angle rate takes in the map (a signed permutation, its own inverse transposed).
  Eigen::VectorXd to_left(const Eigen::VectorXd& x) const;
  Eigen::VectorXd to_right(const Eigen::VectorXd& x_left) const;

  // Whether row r of `states` stands on the left foot: its stance cell "left" or "l" ("right" or "r": the
  // right foot; no stance column: the right foot); other text is an InputError naming row and column.
  static bool left_row(const JointTable& states, std::size_t r);

 private:
  HumanModel<double> right_, left_;
  StanceSwitch<HumanModel<double>, HumanModel<double>> switch_;
  M left_any_;
  Data<M> left_ws_;
  std::array<int, 16> source_{};  // the right model's joint that the left model's joint k reads
  std::array<double, 16> sign_{};
};

}  // namespace humandyn::cli
