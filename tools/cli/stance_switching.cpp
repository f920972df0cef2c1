#include "cli/stance_switching.hpp"

#include "cli/errors.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "text/shown.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace humandyn::cli {

namespace {

// Each link of `right` and its namesake in `left`, both at q = 0 in the world: the same mass, centre of
// mass and rotational inertia, or the name of the first link that differs and how. The left-stance model
// is the body's mirror image (left_stance_description), which is the same body only for a body whose
// left and right sides are mirror images.
std::string first_asymmetry(const HumanModel<double>& right, const HumanModel<double>& left) {
  Data<HumanModel<double>> dr(right), dl(left);
  forward_kinematics(right, dr, HumanModel<double>::JointVector::Zero());
  forward_kinematics(left, dl, HumanModel<double>::JointVector::Zero());
  // every link in the world: its name and inertia (the base link's too)
  const auto world = [](const HumanModel<double>& m, const Data<HumanModel<double>>& d) {
    std::vector<std::pair<std::string, RigidBodyInertia<double>>> links{
        {m.description().base_link_name, m.description().base_body.expressed_in(m.base_pose())}};
    for (int i = 0; i < m.size(); ++i)
      links.emplace_back(m.description().joints[std::size_t(i)].link_name,
                         m.description().joints[std::size_t(i)].body.expressed_in(d.oMi[std::size_t(i)]));
    return links;
  };
  const auto r = world(right, dr), l = world(left, dl);
  double mass = 0, inertia = 0;
  for (const auto& [name, b] : r) {
    mass += b.mass;
    inertia = std::max(inertia, b.inertia.cwiseAbs().maxCoeff());
  }
  for (const auto& [name, b] : r)
    for (const auto& [name_l, b_l] : l) {
      if (name_l != name) continue;
      if (std::abs(b.mass - b_l.mass) > 1e-9 * mass)
        return fmt::format("link '{}' has a mass of {} kg, its mirror image {} kg", text::shown(name),
                           exact_number(b.mass), exact_number(b_l.mass));
      if (b.mass > 0 && (b.com - b_l.com).norm() > 1e-9)
        return fmt::format("the centre of mass of link '{}' lies {} m from its mirror image's", text::shown(name),
                           exact_number((b.com - b_l.com).norm()));
      if ((b.inertia - b_l.inertia).cwiseAbs().maxCoeff() > 1e-9 * inertia)
        return fmt::format("the rotational inertia of link '{}' differs from its mirror image's by {} kg m^2",
                           text::shown(name), exact_number((b.inertia - b_l.inertia).cwiseAbs().maxCoeff()));
    }
  return "";
}

}  // namespace

// Any model error in building the left-stance model and the map (a body of another shape, legs of
// different lengths) is said as what it is for the states file: a body whose feet the column cannot switch.
StanceSwitching::StanceSwitching(const ModelDescription<double>& right, const std::string& file,
                                 const std::string& model) try
    : right_(right),
      left_(left_stance_description(right)),
      switch_(right_, left_),
      left_any_(left_.description()),
      left_ws_(left_any_) {
  const std::string why = "the stance column of " + file + " switches to the left foot through the mirror image of '" +
                          model + "', which is not the same body: ";
  if (const std::string a = first_asymmetry(right_, left_); !a.empty())
    throw UsageError(why + a + " (a left row needs a body whose sides are mirror images)");
  // the signed permutation, read off the state map one unit rate at a time: each joint of the left model
  // moves with exactly one of the right model's, at rate +1 or -1
  std::array<int, 16> found{};
  StanceState<HumanModel<double>> s;
  for (int j = 0; j < 16; ++j) {
    switch_(right_, left_, HumanModel<double>::JointVector::Zero(), HumanModel<double>::JointVector::Unit(j), s);
    for (int k = 0; k < 16; ++k)
      if (std::abs(std::abs(s.qd[k]) - 1) < 1e-9) {
        source_[std::size_t(k)] = j;
        sign_[std::size_t(k)] = s.qd[k] > 0 ? 1 : -1;
        ++found[std::size_t(k)];
      } else if (std::abs(s.qd[k]) > 1e-9) {
        throw UsageError(why + "joint '" + left_.joint_name(k) + "' of the left-stance model turns at " +
                         exact_number(s.qd[k]) + " rad/s with joint '" + right_.joint_name(j) + "' at 1 rad/s");
      }
  }
  for (int k = 0; k < 16; ++k)
    if (found[std::size_t(k)] != 1)
      throw UsageError(why + "joint '" + left_.joint_name(k) + "' of the left-stance model does not turn with " +
                       "exactly one of the body's joints");
} catch (const ModelError& e) {
  throw UsageError("the stance column of " + file +
                   " switches between the feet of a body of the seed's shape, which '" + model +
                   "' is not: " + e.what());
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
    states.fail_at(r, "stance", "'" + text::shown(*stance) + "' is not a stance foot (right, left, r or l)");
  return false;
}

bool StanceSwitching::any_left_row(const JointTable& states) {
  for (std::size_t r = 0; r < states.rows(); ++r)
    if (left_row(states, r)) return true;
  return false;
}

StancePlacement::StancePlacement(const M& model, const BaseColumns& base, const JointTable& states,
                                 const Pose<double>& start)
    : model_(model), base_(base), states_(states), moving_(base.any(states)), placement_(start) {}

const Pose<double>& StancePlacement::at(std::size_t r, bool left, const Data<M>& data) {
  if (left) {
    // the left foot, the first time a row stands on it: the link of the model that carries the
    // left-stance model's base, and that base frame seen from the link's frame (stance.hpp)
    if (!left_foot_) {
      try {
        const ModelDescription<double>& d = model_.description();
        const HumanModel<double> right(d), left_stance(left_stance_description(d));
        const StanceSwitch<HumanModel<double>, HumanModel<double>> to_left(right, left_stance);
        if (to_left.base_body() < 1) throw ModelError("the left-stance model stands on the right model's base");
        left_foot_.emplace(to_left.base_body() - 1, to_left.base_offset());
      } catch (const ModelError& e) {
        // (a usage error, as in id and fd: the row is well formed, the model cannot take it)
        states_.refuse_at(
            r, "stance",
            std::string("the left foot needs a body of the seed's shape with mirror-image sides: ") + e.what());
      }
    }
    const auto& [link, offset] = *left_foot_;
    const Pose<double>& foot = data.oMi[std::size_t(link)];
    if (moving_)  // groups left out: the left foot's frame where the body puts it now
      held_ = base_.read(states_, r, placement_ * foot * offset).pose * offset.inverse();
    else if (r == 0 || !previous_left_)  // the left foot comes down where it is
      held_ = placement_ * foot;
    placement_ = held_ * foot.inverse();
  } else if (moving_) {
    const Pose<double>& home = model_.base_pose();
    placement_ = base_.read(states_, r, home).pose * home.inverse();
  }  // else the right foot stays where it was
  previous_left_ = left;
  return placement_;
}

}  // namespace humandyn::cli
