// Reading a URDF document into plain data, with every element's line for messages. The XML is
// checked element by element first (structure, names, numbers), so that each error names its line;
// urdfdom then reads the values.
#pragma once

#include "humandyn/model.hpp"

#include <string>
#include <vector>

namespace humandyn::urdf::detail {

enum class JointType { Revolute, Continuous, Prismatic, Fixed, Floating, Planar };

struct UrdfLink {
  std::string name;
  int line = 0;
  RigidBodyInertia<double> body;  // in the link's frame (centre of mass and inertia about it)
  int parent_joint = -1;          // the joint this link is the child of, -1 for the root
  std::vector<int> child_joints;  // document order
};

struct UrdfJoint {
  std::string name;
  int line = 0;
  JointType type = JointType::Fixed;
  int parent = -1, child = -1;                      // link indices
  Pose<double> origin;                              // child link frame in the parent link frame at q = 0
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // unit, in the child link frame
  bool mimic = false;
};

struct UrdfDocument {
  std::string source;             // file name, for messages
  std::string name;               // the robot's name
  std::vector<UrdfLink> links;    // document order
  std::vector<UrdfJoint> joints;  // document order
  int root = -1;

  // "source:line: joint 'name'" and friends, the start of every message about an element
  std::string where_joint(int j) const;
  std::string where_link(int l) const;
  int find_link(const std::string& link_name) const;
  int find_joint(const std::string& joint_name) const;
};

// Parses and validates; throws Error. With `balance_inertia`, a link inertia that violates the
// triangle inequality gets the mean of its principal moments about every axis, and `warnings` a line.
UrdfDocument read_urdf_document(const std::string& xml, const std::string& source, bool balance_inertia,
                                std::vector<std::string>& warnings);

const char* type_name(JointType t);

}  // namespace humandyn::urdf::detail
