// A drawing of a model in one pose, as SVG: a front view (the y-z plane, seen from ahead, so the body's
// left is on the right) and a side view (the x-z plane, seen from the body's right, forward to the
// right), side by side. Links are segments between their frame origins, joints are dots on their axes,
// and every joint carries a label with its number, name and torque.
#pragma once

#include "humandyn/model.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace humandyn::cli {

struct BodyDrawing {
  std::string title;               // first line, e.g. the model and the scenario
  std::vector<std::string> notes;  // further lines under the title
  Eigen::VectorXd q;               // joint angles (rad)
  Eigen::VectorXd tau;             // the torque to print beside each joint (N m)
};

// The SVG document (UTF-8 text).
std::string body_svg(const AnyModel<double>& model, const BodyDrawing& drawing);

}  // namespace humandyn::cli
