// Every named pose is the pose its name says, by forward kinematics (poses.hpp): the home pose stands
// upright, `seated` sits with thighs forward and shanks vertical, `left_arm_forward` holds the left arm
// horizontal in front. And every `--lock` example in the docs and in the command line's help texts is
// a named pose, so none of them can say "seated" and bend a knee the wrong way.
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/poses.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace test_poses {

namespace {

using namespace humandyn;
using M = HumanModel<double>;
using Q = M::JointVector;

// The joint centres and end points of the seed body, each the origin of a link frame (or the base).
class Body {
 public:
  explicit Body(const SeedParameters& p) : model_(human_description(p)), data_(model_) {}
  const M& model() const { return model_; }

  void set(const Q& q) { forward_kinematics(model_, data_, q); }

  // The origin of link `link`'s frame in the world (the base link: the base frame's).
  Eigen::Vector3d at(const std::string& link) const {
    if (link == model_.description().base_link_name) return model_.base_pose().p;
    for (int i = 0; i < model_.size(); ++i)
      if (model_.description().joints[std::size_t(i)].link_name == link) return data_.oMi[std::size_t(i)].p;
    ADD_FAILURE() << "no link " << link;
    return Eigen::Vector3d::Zero();
  }
  // The unit vector from point a to point b.
  Eigen::Vector3d direction(const std::string& a, const std::string& b) const { return (at(b) - at(a)).normalized(); }

 private:
  M model_;
  Data<M> data_;
};

// Where the joints are (link frames of the seed body, Table 1): the right ankle is the base frame,
// the right knee frame 1 (r_shank), the right hip frame 2 (r_thigh), the left hip frame 13
// (l_hip_link), the left knee frame 14 (l_thigh), the left ankle frame 15 (l_shank), the left sole
// frame 16 (l_foot), the base of the neck frame 6 (upper_body), the pelvis frame 4, the left shoulder,
// elbow and wrist frames 7, 8, 9, the right ones 10, 11, 12.
const std::string r_ankle = "r_foot", r_knee = "r_shank", r_hip = "r_thigh", l_hip = "l_hip_link", l_knee = "l_thigh",
                  l_ankle = "l_shank", l_sole = "l_foot", pelvis = "pelvis", neck = "upper_body",
                  l_shoulder = "l_shoulder_link", l_elbow = "l_upper_arm", l_wrist = "l_forearm",
                  r_shoulder = "r_shoulder_link", r_elbow = "r_upper_arm", r_wrist = "r_forearm";

const Eigen::Vector3d forward(1, 0, 0), down(0, 0, -1), up(0, 0, 1);

std::vector<SeedParameters> bodies() { return {default_parameters(), female_parameters(), paper_parameters()}; }

// Whether two unit vectors agree within `tol` (each coordinate).
::testing::AssertionResult along(const Eigen::Vector3d& got, const Eigen::Vector3d& want, double tol) {
  if ((got - want).cwiseAbs().maxCoeff() <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "points along (" << got.transpose() << "), not (" << want.transpose() << ")";
}

// The claims of `seated`, to `tol` in every direction and `tol` m in every height.
void expect_seated(const Body& b, const Body& home, double tol) {
  for (const auto& [hip, knee, ankle] : {std::array{r_hip, r_knee, r_ankle}, std::array{l_hip, l_knee, l_ankle}}) {
    EXPECT_TRUE(along(b.direction(hip, knee), forward, tol)) << "thigh " << hip << " -> " << knee;
    EXPECT_TRUE(along(b.direction(knee, ankle), down, tol)) << "shank " << knee << " -> " << ankle;
    EXPECT_LE((b.at(ankle) - home.at(ankle)).cwiseAbs().maxCoeff(), tol) << "ankle " << ankle << " where it stands";
  }
  EXPECT_NEAR(b.at(l_sole).z(), home.at(l_sole).z(), tol) << "the left sole on the ground";
  EXPECT_TRUE(along(b.direction(pelvis, neck), up, tol)) << "the trunk upright";
  EXPECT_TRUE(along(b.direction(l_shoulder, l_wrist), down, tol)) << "the arms hang";
}

TEST(NamedPoses, HomeStandsUprightWithArmsHanging) {
  for (const auto& p : bodies()) {
    Body b(p);
    b.set(Q::Zero());
    for (const auto& [top, bottom] : {std::pair{r_hip, r_knee},
                                      {r_knee, r_ankle},
                                      {l_hip, l_knee},
                                      {l_knee, l_ankle},
                                      {l_ankle, l_sole},
                                      {l_shoulder, l_elbow},
                                      {l_elbow, l_wrist},
                                      {r_shoulder, r_elbow},
                                      {r_elbow, r_wrist},
                                      {neck, pelvis}})
      EXPECT_TRUE(along(b.direction(top, bottom), down, 1e-12)) << p.name << ": " << top << " -> " << bottom;
    EXPECT_NEAR(b.at(r_ankle).z(), b.at(l_ankle).z(), 1e-12) << p.name << ": both ankles at one height";
  }
}

TEST(NamedPoses, SeatedHasThighsForwardShanksVerticalTrunkUpright) {
  for (const auto& p : bodies()) {
    Body home(p), b(p);
    home.set(Q::Zero());
    b.set(poses::angles(b.model(), poses::seated));
    SCOPED_TRACE(p.name);
    expect_seated(b, home, 1e-12);
    // the hips at knee height, a thigh's length behind the knees
    EXPECT_NEAR(b.at(r_hip).z(), b.at(r_knee).z(), 1e-12);
    EXPECT_NEAR(b.at(l_hip).z(), b.at(l_knee).z(), 1e-12);
  }
}

TEST(NamedPoses, LeftArmForwardIsHorizontalInFrontWithTheRightArmHanging) {
  for (const auto& p : bodies()) {
    Body b(p);
    b.set(poses::angles(b.model(), poses::left_arm_forward));
    SCOPED_TRACE(p.name);
    EXPECT_TRUE(along(b.direction(l_shoulder, l_elbow), forward, 1e-12));
    EXPECT_TRUE(along(b.direction(l_elbow, l_wrist), forward, 1e-12));
    EXPECT_TRUE(along(b.direction(r_shoulder, r_wrist), down, 1e-12));
  }
}

// A pose whose angles are rounded to two decimals, as --lock examples print them, is still that pose
// to within the rounding (|dq| <= 0.005 rad per joint, at most four joints in a row).
TEST(NamedPoses, LockTextIsThePoseToItsRounding) {
  EXPECT_EQ(poses::lock_text(poses::seated), "r_knee_pitch=-1.57,r_hip_pitch=1.57,l_hip_pitch=-1.57,l_knee_pitch=1.57");
  Body home(default_parameters()), b(default_parameters());
  home.set(Q::Zero());
  Q q = poses::angles(b.model(), poses::seated);
  for (auto& x : q) x = std::round(100 * x) / 100;
  b.set(q);
  expect_seated(b, home, 0.02);
}

// Every `--lock J=A,...` in `text`.
std::vector<std::string> lock_examples(const std::string& text) {
  static const std::regex lock(R"(--lock[ =]([A-Za-z_0-9]+=-?[0-9.]+(,[A-Za-z_0-9]+=-?[0-9.]+)*))");
  std::vector<std::string> out;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), lock); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1].str());
  return out;
}

// Each example must be a named pose's lock text.
void expect_named_locks(const std::string& text, const std::string& where, int at_least) {
  const auto examples = lock_examples(text);
  EXPECT_GE(int(examples.size()), at_least) << where << ": expected a --lock example";
  for (const auto& e : examples)
    EXPECT_EQ(e, poses::lock_text(poses::seated)) << where << ": --lock " << e << " is not a named pose (poses.hpp)";
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << "cannot read " << path;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(NamedPoses, EveryLockInTheDocsIsANamedPose) {
  expect_named_locks(read_text(HUMANDYN_SOURCE_DIR "/docs/scenes.md"), "docs/scenes.md", 1);
  expect_named_locks(read_text(HUMANDYN_SOURCE_DIR "/README.md"), "README.md", 0);
}

#ifdef HUMANDYN_CLI
std::string help_of(const std::string& command) {
  std::string out;
  if (FILE* pipe = popen((std::string(HUMANDYN_CLI) + " " + command + " --help").c_str(), "r")) {
    char buffer[4096];
    for (std::size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) out.append(buffer, n);
    EXPECT_EQ(pclose(pipe), 0) << command << " --help";
  }
  return out;
}

TEST(NamedPoses, EveryLockInTheHelpTextsIsANamedPose) {
  for (const char* command : {"id", "simulate"})
    expect_named_locks(help_of(command), command + std::string(" --help"), 1);
  expect_named_locks(help_of("fd"), "fd --help", 0);
}
#endif

}  // namespace

}  // namespace test_poses
