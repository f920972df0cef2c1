// humandyn: real-time dynamics of a 16-joint human body in five DH chains.
#pragma once

#include "humandyn/shape.hpp"
#include "humandyn/model.hpp"
#include "humandyn/data.hpp"
#include "humandyn/anthropometry.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/algorithm/crba.hpp"
#include "humandyn/algorithm/ldlt.hpp"
#include "humandyn/algorithm/aba.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/energy.hpp"
#include "humandyn/servo.hpp"
#include "humandyn/integrators.hpp"
#include "humandyn/scene.hpp"
#include "humandyn/stance.hpp"
