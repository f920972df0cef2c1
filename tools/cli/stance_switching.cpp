#include "cli/stance_switching.hpp"

#include "cli/errors.hpp"

#include <cmath>

namespace humandyn::cli {

namespace {

HumanModel<double> seed_shaped(const ModelDescription<double>& d, const std::string& file, const std::string& model) {
  try {
    return HumanModel<double>(d);
  } catch (const ModelError& e) {
    throw UsageError("the stance column of " + file +
                     " switches between the feet of a body of the seed's shape, which '" + model +
                     "' is not: " + e.what());
  }
}

}  // namespace

StanceSwitching::StanceSwitching(const ModelDescription<double>& right, const std::string& file,
                                 const std::string& model)
    : right_(seed_shaped(right, file, model)),
      left_(left_stance_description(right)),
      switch_(right_, left_),
      left_any_(left_.description()),
      left_ws_(left_any_) {
  // the signed permutation, read off the state map one unit rate at a time
  StanceState<HumanModel<double>> s;
  for (int j = 0; j < 16; ++j) {
    switch_(right_, left_, HumanModel<double>::JointVector::Zero(), HumanModel<double>::JointVector::Unit(j), s);
    for (int k = 0; k < 16; ++k)
      if (std::abs(std::abs(s.qd[k]) - 1) < 1e-6) {
        source_[std::size_t(k)] = j;
        sign_[std::size_t(k)] = s.qd[k] > 0 ? 1 : -1;
      }
  }
}

Pose<double> StanceSwitching::to_left(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Eigen::VectorXd& lq,
                                      Eigen::VectorXd& lqd) const {
  StanceState<HumanModel<double>> s;
  switch_(right_, left_, HumanModel<double>::JointVector(q), HumanModel<double>::JointVector(qd), s);
  lq = s.q;
  lqd = s.qd;
  return s.base_pose;
}

Eigen::VectorXd StanceSwitching::to_left(const Eigen::VectorXd& x) const {
  Eigen::VectorXd l(16);
  for (int k = 0; k < 16; ++k) l[k] = sign_[std::size_t(k)] * x[source_[std::size_t(k)]];
  return l;
}

Eigen::VectorXd StanceSwitching::to_right(const Eigen::VectorXd& x_left) const {
  Eigen::VectorXd x(16);
  for (int k = 0; k < 16; ++k) x[source_[std::size_t(k)]] = sign_[std::size_t(k)] * x_left[k];
  return x;
}

bool StanceSwitching::left_row(const JointTable& states, std::size_t r) {
  const std::string* stance = states.text(r, "stance");
  if (!stance) return false;
  if (*stance == "left" || *stance == "l") return true;
  if (*stance != "right" && *stance != "r")
    states.fail_at(r, "stance", "'" + *stance + "' is not a stance foot (right, left, r or l)");
  return false;
}

}  // namespace humandyn::cli
