// The right- and left-stance models of one body, for the commands whose rows switch the stance foot (a
// `stance` column): a left row's state is the right-stance model's, carried to the left-stance model by
// the exact state map (stance.hpp) and its results carried back.
#pragma once

#include "cli/base_columns.hpp"
#include "cli/joint_table.hpp"
#include "humandyn/data.hpp"
#include "humandyn/model.hpp"
#include "humandyn/stance.hpp"

#include <array>
#include <optional>
#include <string>
#include <utility>

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
  // Whether any row of `states` stands on the left foot (left_row's errors for a bad cell): a file whose
  // rows all stand on the right foot needs no switching, and its body no mirror image of itself.
  static bool any_left_row(const JointTable& states);

 private:
  HumanModel<double> right_, left_;
  StanceSwitch<HumanModel<double>, HumanModel<double>> switch_;
  M left_any_;
  Data<M> left_ws_;
  std::array<int, 16> source_{};  // the right model's joint that the left model's joint k reads
  std::array<double, 16> sign_{};
};

// Where the body of a states file stands, row by row, as `view` and `motion export` place it:
// world = placement * the model's world. A row's stance foot stands where the base columns put it when
// the file has them (groups left out: at rest where the model puts that foot); without them it is held
// still: the right foot where `start` puts the model, a left foot where it came down. Each row's forward
// kinematics is given (data.oMi at the row's angles).
class StancePlacement {
 public:
  using M = AnyModel<double>;

  StancePlacement(const M& model, const BaseColumns& base, const JointTable& states,
                  const Pose<double>& start = Pose<double>{});

  // The placement of row r; InputError naming the stance cell when the row stands on the left foot and
  // the body cannot (not of the seed's shape, or sides that are not mirror images).
  const Pose<double>& at(std::size_t r, bool left, const Data<M>& data);

  // The link that carries the left-stance model's base (the left foot), -1 until a row stood on it.
  int left_foot_link() const { return left_foot_ ? left_foot_->first : -1; }

 private:
  const M& model_;
  const BaseColumns& base_;
  const JointTable& states_;
  bool moving_;
  std::optional<std::pair<int, Pose<double>>> left_foot_;  // the link, and the left base frame seen from it
  Pose<double> placement_;
  Pose<double> held_;  // the left foot's link frame in the world while the body stands on it
  bool previous_left_ = false;
};

}  // namespace humandyn::cli
