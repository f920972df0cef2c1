// The BVH reader and writer, forward kinematics of the BVH skeleton, the landmark map and the CMU clips.
#include "humandyn/bvh.hpp"
#include "humandyn/motion/fit.hpp"
#include "humandyn/motion/import.hpp"

#include "fuzz/bvh_inputs.hpp"
#include "support/long_runs.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace test_bvh {

namespace {

namespace hm = humandyn::motion;
using Eigen::Vector3d;

// Eigen's rotation about file axis 'X', 'Y' or 'Z' by degrees.
Eigen::Matrix3d rot(char axis, double degrees) {
  const Vector3d u = axis == 'X' ? Vector3d::UnitX() : axis == 'Y' ? Vector3d::UnitY() : Vector3d::UnitZ();
  return Eigen::AngleAxisd(degrees * M_PI / 180, u).toRotationMatrix();
}

// The message of the BvhError that `f` throws ("" if none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const hm::BvhError& e) {
    return e.what();
  }
  return "";
}

// A root with six channels in `root_channels` order and a child with three rotations in `child_order`
// ("ZYX": Zrotation Yrotation Xrotation), an End Site below it; one frame of `values`.
std::string two_joints(const std::string& root_channels, const std::string& child_order, const std::string& values) {
  std::string child;
  for (const char c : child_order) child += std::string(" ") + c + "rotation";
  return "HIERARCHY\nROOT root\n{\n\tOFFSET 1 2 3\n\tCHANNELS 6 " + root_channels +
         "\n\tJOINT child\n\t{\n\t\tOFFSET 0.5 -1 2\n\t\tCHANNELS 3" + child +
         "\n\t\tEnd Site\n\t\t{\n\t\t\tOFFSET 0 1 0\n\t\t}\n\t}\n}\nMOTION\nFrames: 1\nFrame Time: 0.01\n" + values +
         "\n";
}

constexpr hm::WorldOptions file_axes{1.0, hm::UpAxis::z};  // the world map is the identity

// Every rotation order on the root and on a child, against Eigen's AngleAxis products R_1 R_2 R_3 in the
// order listed, applied to column vectors; position channels interleaved with the rotations.
TEST(BvhKinematics, EveryRotationOrderAgainstAngleAxis) {
  std::string order = "XYZ";
  int cases = 0;
  do {
    // root channels: rotation 1, Xposition, rotation 2, Yposition, rotation 3, Zposition
    const std::string root_channels = std::string(1, order[0]) + "rotation Xposition " + order[1] +
                                      "rotation Yposition " + order[2] + "rotation Zposition";
    const std::array<double, 3> ra{30, -50, 110}, ca{-20, 75, 40};
    const Vector3d t(0.25, -0.75, 1.5);
    const std::string values = std::to_string(ra[0]) + " " + std::to_string(t.x()) + " " + std::to_string(ra[1]) + " " +
                               std::to_string(t.y()) + " " + std::to_string(ra[2]) + " " + std::to_string(t.z()) + " " +
                               std::to_string(ca[0]) + " " + std::to_string(ca[1]) + " " + std::to_string(ca[2]);
    const std::string reversed(order.rbegin(), order.rend());  // the child lists its rotations in the other order
    SCOPED_TRACE(order);
    const hm::BvhClip clip = hm::parse_bvh(two_joints(root_channels, reversed, values), "two.bvh");
    ASSERT_EQ(clip.joints.size(), 3u);
    ASSERT_EQ(clip.channel_count(), 9);
    const Eigen::Matrix3d r_root = rot(order[0], ra[0]) * rot(order[1], ra[1]) * rot(order[2], ra[2]);
    const Eigen::Matrix3d r_child = rot(reversed[0], ca[0]) * rot(reversed[1], ca[1]) * rot(reversed[2], ca[2]);
    const Vector3d root = Vector3d(1, 2, 3) + t;
    const Vector3d child = root + r_root * Vector3d(0.5, -1, 2);
    const Vector3d end = child + r_root * r_child * Vector3d(0, 1, 0);
    const auto p = hm::joint_positions(clip, 0, file_axes);
    EXPECT_LT((p[0] - root).norm(), 1e-12);
    EXPECT_LT((p[1] - child).norm(), 1e-12);
    EXPECT_LT((p[2] - end).norm(), 1e-12);
    ++cases;
  } while (std::next_permutation(order.begin(), order.end()));
  EXPECT_EQ(cases, 6);
}

// Position channels on a child joint add to its OFFSET; only some axes may be given.
TEST(BvhKinematics, PositionChannelsOnAChild) {
  const std::string text =
      "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Zrotation\nJOINT b\n{\nOFFSET 1 0 0\n"
      "CHANNELS 2 Yposition Xposition\n}\n}\nMOTION\nFrames: 1\nFrame Time: 1\n90 2 3\n";
  const auto p = hm::joint_positions(hm::parse_bvh(text), 0, file_axes);
  // b's local translation (1 + 3, 2, 0), turned 90 degrees about z
  EXPECT_LT((p[1] - Vector3d(-2, 4, 0)).norm(), 1e-12);
}

// Y-up files: (x, y, z) -> s (z, x, y), a proper rotation; Z-up files keep their axes; the unit scales.
TEST(BvhKinematics, WorldMap) {
  const Vector3d p(1, 2, 3);
  EXPECT_EQ(hm::to_world(p, {2.0, hm::UpAxis::y}), Vector3d(6, 2, 4));
  EXPECT_EQ(hm::to_world(p, {2.0, hm::UpAxis::z}), Vector3d(2, 4, 6));
  Eigen::Matrix3d m;
  for (int k = 0; k < 3; ++k) m.col(k) = hm::to_world(Vector3d::Unit(k), {1.0, hm::UpAxis::y});
  EXPECT_EQ(m.determinant(), 1.0);
  EXPECT_DOUBLE_EQ(hm::cmu_metres_per_unit, 0.056444444444444444);
  const hm::BvhClip clip = hm::parse_bvh(
      two_joints("Xposition Yposition Zposition Zrotation Yrotation Xrotation", "ZYX", "0 0 0 0 0 0 0 0 0"));
  EXPECT_NE(error_of([&] {
              hm::joint_positions(clip, 0, {0.0, hm::UpAxis::y});
            }).find("positive number of metres"),
            std::string::npos);
  EXPECT_NE(error_of([&] { hm::joint_positions(clip, 1); }).find("frame 1 is not in the clip's 0..0"),
            std::string::npos);
}

// A tiny file read exactly: names with blanks, End Sites, several roots, CRLF, a byte-order mark.
TEST(BvhReader, Structure) {
  const std::string text =
      "\xEF\xBB\xBFHIERARCHY\r\nROOT Bip01 Pelvis\r\n{\r\n  OFFSET 0 +1.5 -2e-3\r\n  CHANNELS 3 Xposition Yposition "
      "Zposition\r\n  End Site\r\n  {\r\n    OFFSET 0 1 0\r\n  }\r\n}\r\nROOT prop\r\n{\r\n OFFSET 1 1 1\r\n CHANNELS "
      "1 "
      "Xrotation\r\n}\r\nMOTION\r\nFrames: 2\r\nFrame Time: .0083333\r\n1 2 3 4\r\n\t5 6 7 8  \r\n\r\n";
  const hm::BvhClip clip = hm::parse_bvh(text, "tiny.bvh");
  ASSERT_EQ(clip.joints.size(), 3u);
  EXPECT_EQ(clip.joints[0].name, "Bip01 Pelvis");
  EXPECT_EQ(clip.joints[0].offset, Vector3d(0, 1.5, -2e-3));
  EXPECT_TRUE(clip.joints[1].end_site);
  EXPECT_EQ(clip.joints[1].parent, 0);
  EXPECT_EQ(clip.joints[1].line, 6);
  EXPECT_EQ(clip.joints[2].name, "prop");
  EXPECT_EQ(clip.joints[2].parent, -1);
  EXPECT_EQ(clip.frame_time, 0.0083333);
  EXPECT_EQ(clip.frame_count(), 2);
  EXPECT_EQ(clip.values, (std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(clip.find("prop"), 2);
  EXPECT_EQ(clip.find("nothing"), -1);
  // the same file with old Mac OS line ends (a lone \r): the same clip, on the same lines
  std::string mac;
  for (std::size_t i = 0; i < text.size(); ++i)
    if (!(text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n')) mac += text[i] == '\n' ? '\r' : text[i];
  ASSERT_EQ(mac.find('\n'), std::string::npos);
  const hm::BvhClip same = hm::parse_bvh(mac, "mac.bvh");
  ASSERT_EQ(same.joints.size(), 3u);
  EXPECT_EQ(same.joints[1].line, 6);
  EXPECT_EQ(same.values, clip.values);
  EXPECT_EQ(same.frame_time, clip.frame_time);
}

// Every malformed file is an error naming file, line and column and what was expected.
TEST(BvhReader, MalformedFilesNameLineAndColumn) {
  const std::string head = "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 2 Xrotation Yrotation\n}\n";
  const std::string good_motion = "MOTION\nFrames: 1\nFrame Time: 0.1\n1 2\n";
  const std::vector<std::pair<std::string, std::string>> cases{
      {"", "bad.bvh:1:1: expected HIERARCHY at the start of the file, found the end of the file"},
      {"HIERARCHI\n", "bad.bvh:1:1: expected HIERARCHY at the start of the file, found 'HIERARCHI'"},
      {"HIERARCHY\nJOINT a\n", "bad.bvh:2:1: expected ROOT, found 'JOINT'"},
      {"HIERARCHY\nROOT a\n", "bad.bvh:2:7: expected '{' after ROOT a, found the end of the file"},
      {"HIERARCHY\nROOT\n{\n", "bad.bvh:2:5: expected the name of the ROOT on its line"},
      {"HIERARCHY\nROOT a\nOFFSET 0 0 0\n", "bad.bvh:3:1: expected '{' after ROOT a, found 'OFFSET'"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 x 0\n", "bad.bvh:4:10: 'x' is not a number (OFFSET value 2 of 3)"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 nan 0\n", "bad.bvh:4:10: 'nan' is not a finite number (OFFSET value 2 of 3)"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 1e999 0\n", "bad.bvh:4:10: '1e999' is out of the range of a double"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 7\n", "bad.bvh:5:10: the number of channels '7' is larger than 6"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS -1\n",
       "bad.bvh:5:10: expected the number of channels (a whole number), found '-1'"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Wrotation\n",
       "bad.bvh:5:12: expected channel 1 of 1 (Xposition, Yposition, Zposition, Xrotation, Yrotation or Zrotation), "
       "found 'Wrotation'"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 2 Xrotation Xrotation\n",
       "bad.bvh:5:22: channel Xrotation listed twice in joint 'a'"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 3 Xrotation Yrotation\n}\n",
       "bad.bvh:5:31: expected channel 3 of 3 (Xposition, Yposition, Zposition, Xrotation, Yrotation or Zrotation), "
       "found the end of the line"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0\nCHANNELS 0\n",
       "bad.bvh:4:11: expected OFFSET value 3 of 3, found the end of the line"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation Yrotation\n}\n",
       "bad.bvh:5:22: channel Yrotation beyond the count given after CHANNELS in joint 'a'"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\nJOINT a\n",
       "bad.bvh:6:7: duplicate joint name 'a' (first on line 2)"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\nEnd Site\n{\nOFFSET 0 0 0\nCHANNELS 0\n",
       "bad.bvh:9:1: expected '}' closing the End Site (an End Site has only an OFFSET), found 'CHANNELS'"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\nBONE b\n",
       "bad.bvh:6:1: expected JOINT, End Site or '}' in joint 'a', found 'BONE'"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\nMOTION\n",
       "bad.bvh:7:1: the hierarchy has no channels, so the frames hold nothing"},
      {head + "MOTIONS\n", "bad.bvh:7:1: expected ROOT or MOTION after the hierarchy, found 'MOTIONS'"},
      {head + "MOTION\nFrame Time: 0.1\n", "bad.bvh:8:1: expected 'Frames:' after MOTION, found 'Frame'"},
      {head + "MOTION\nFrames:\n1\n", "bad.bvh:8:8: expected the number of frames, found the end of the line"},
      {head + "MOTION\nFrames: 1\nFrame\nTime: 1\n",
       "bad.bvh:9:6: expected 'Time:' after 'Frame', found the end of the line"},
      {head + "MOTION\nFrames: 1.5\n", "bad.bvh:8:9: expected the number of frames (a whole number), found '1.5'"},
      {head + "MOTION\nFrames: 1 2\n", "bad.bvh:8:11: unexpected '2' after the number of frames"},
      {head + "MOTION\nFrames: 1\n1 2\n", "bad.bvh:9:1: expected 'Frame Time:' after 'Frames:', found '1'"},
      {head + "MOTION\nFrames: 1\nFrame Time: -0.1\n1 2\n", "bad.bvh:9:13: the frame time must be positive"},
      {head + "MOTION\nFrames: 1\nFrame Time: 0\n1 2\n", "bad.bvh:9:13: the frame time must be positive"},
      {head + "MOTION\nFrames: 1\nFrame Time: inf\n1 2\n", "bad.bvh:9:13: 'inf' is not a finite number"},
      {head + "MOTION\nFrames: 2\nFrame Time: 0.1\n1 2\n",
       "bad.bvh:10:4: the file ends after 1 of the 2 frames that 'Frames:' announces"},
      {head + "MOTION\nFrames: 1\nFrame Time: 0.1\n1\n",
       "bad.bvh:10:2: frame 1 has 1 values, the hierarchy 2 channels"},
      {head + "MOTION\nFrames: 1\nFrame Time: 0.1\n1 2 3\n",
       "bad.bvh:10:5: frame 1 has more than the hierarchy's 2 channel values"},
      {head + "MOTION\nFrames: 1\nFrame Time: 0.1\n1 NaN\n",
       "bad.bvh:10:3: 'NaN' is not a finite number (frame 1, value 2)"},
      {head + "MOTION\nFrames: 1\nFrame Time: 0.1\n1 2,5\n", "bad.bvh:10:3: '2,5' is not a number (frame 1, value 2)"},
      {head + "MOTION\nFrames: 1\nFrame Time: 0.1\n1 2\n3 4\n",
       "bad.bvh:11:1: a motion line beyond the 1 frames that 'Frames:' announces"},
      {head + "MOTION\nFrames: 2\nFrame Time: 0.1\n1 2\n\n3 4\n", "bad.bvh:11:1: frame 2 has 0 values"},
      {"HIERARCHY\nROOT a\tb\x01\n", "bad.bvh:2:6: joint name 'a\\tb<U+0001>' has a control character"},
      {"HIERARCHY\nROOT a\xC2\x85\n", "bad.bvh:2:6: joint name 'a<U+0085>' has a control character"},   // C1
      {"HIERARCHY\nROOT caf\xE9\n", "bad.bvh:2:6: joint name 'caf<0xE9>' is not UTF-8 (byte <0xE9>)"},  // Latin-1
      // the brace on the name's line: the name is the rest of the line, which is refused
      {"HIERARCHY\nROOT Hips {\n",
       "bad.bvh:2:6: joint name 'Hips {' ends in '{': the name stands alone on its line, the '{' on the next"},
      {"HIERARCHY\nROOT\tHips\t{\n",  // (a tab, not a control character for the message to speak of)
       "bad.bvh:2:6: joint name 'Hips\\t{' ends in '{': the name stands alone on its line, the '{' on the next"},
      {"HIERARCHY\nROOT {\n", "bad.bvh:2:6: expected the name of the ROOT on its line, before its '{'"},
  };
  for (const auto& [text, expected] : cases) {
    SCOPED_TRACE(text);
    const std::string what = error_of([&t = text] { hm::parse_bvh(t, "bad.bvh"); });
    EXPECT_EQ(what.substr(0, expected.size()), expected) << what;
  }
  EXPECT_NO_THROW(hm::parse_bvh(head + good_motion, "good.bvh"));
  // a brace inside a name is the name's
  EXPECT_EQ(hm::parse_bvh("HIERARCHY\nROOT Bone{1}\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\n"
                          "MOTION\nFrames: 1\nFrame Time: 0.1\n5\n",
                          "brace.bvh")
                .joints.at(0)
                .name,
            "Bone{1}");
  EXPECT_NE(error_of([] { hm::read_bvh_file("/nonexistent/clip.bvh"); }).find("/nonexistent/clip.bvh: cannot open"),
            std::string::npos);
}

// The writer's text reads back to the same clip, bit for bit, and writing it again gives the same text.
TEST(BvhWriter, RoundTripIsExact) {
  hm::BvhClip clip = hm::parse_bvh(
      two_joints("Xposition Yposition Zposition Zrotation Yrotation Xrotation", "YXZ", "0.1 0.2 0.3 1 2 3 4 5 6"),
      "two.bvh");
  // values no decimal text of few digits holds: thirds, tiny and huge numbers, negative zero
  clip.values.clear();
  for (int f = 0; f < 5; ++f)
    for (int c = 0; c < clip.channel_count(); ++c)
      clip.values.push_back(std::pow(-1.0 / 3, f + c) * std::exp(40.0 * (c - 4)));
  clip.values[3] = -0.0;
  clip.frame_time = 1.0 / 120;
  clip.joints[0].offset = Vector3d(M_PI, -1e-300, 1e300);
  const std::string text = hm::to_bvh(clip);
  const hm::BvhClip back = hm::parse_bvh(text, "back.bvh");
  ASSERT_EQ(back.joints.size(), clip.joints.size());
  for (std::size_t i = 0; i < clip.joints.size(); ++i) {
    EXPECT_EQ(back.joints[i].name, clip.joints[i].name);
    EXPECT_EQ(back.joints[i].parent, clip.joints[i].parent);
    EXPECT_EQ(back.joints[i].offset, clip.joints[i].offset);
    EXPECT_EQ(back.joints[i].channels, clip.joints[i].channels);
    EXPECT_EQ(back.joints[i].end_site, clip.joints[i].end_site);
  }
  EXPECT_EQ(back.frame_time, clip.frame_time);
  ASSERT_EQ(back.values.size(), clip.values.size());
  for (std::size_t k = 0; k < clip.values.size(); ++k)
    EXPECT_EQ(std::signbit(back.values[k]), std::signbit(clip.values[k])) << k;
  EXPECT_EQ(back.values, clip.values);
  EXPECT_EQ(hm::to_bvh(back), text);
}

// A hierarchy built in code, with siblings and several End Sites, nests as its parents say.
TEST(BvhWriter, NestsJointsBuiltInCode) {
  hm::BvhClip clip;
  clip.source = "code";
  const auto add = [&](std::string name, int parent, bool end = false) {
    hm::BvhJoint j;
    j.name = std::move(name);
    j.parent = parent;
    j.end_site = end;
    if (!end) j.channels = {hm::Channel::Xrotation};
    clip.joints.push_back(j);
  };
  add("root", -1);
  add("left", 0);
  add("", 1, true);
  add("right", 0);
  add("right tip", 3);
  add("", 4, true);
  clip.frame_time = 0.5;
  clip.values = {1, 2, 3, 4, 5, 6, 7, 8};
  const hm::BvhClip back = hm::parse_bvh(hm::to_bvh(clip));
  ASSERT_EQ(back.joints.size(), clip.joints.size());
  for (std::size_t i = 0; i < clip.joints.size(); ++i) EXPECT_EQ(back.joints[i].parent, clip.joints[i].parent) << i;
  EXPECT_EQ(back.joints[4].name, "right tip");
  EXPECT_EQ(back.frame_count(), 2);

  // what no BVH file can hold is refused
  const auto refused = [&](auto change, const std::string& why) {
    hm::BvhClip bad = clip;
    change(bad);
    const std::string what = error_of([&] { hm::to_bvh(bad); });
    EXPECT_NE(what.find("code: cannot be written as BVH: " + why), std::string::npos) << "'" << what << "'";
  };
  refused([](hm::BvhClip& c) { c.joints[4].parent = 1; },
          "joint 4 ('right tip') does not follow its parent depth first (parent index 1)");
  refused([](hm::BvhClip& c) { c.joints[3].parent = 2; }, "an End Site has a child ('right')");
  refused([](hm::BvhClip& c) { c.joints[3].name = "left"; }, "duplicate joint name 'left'");
  refused([](hm::BvhClip& c) { c.joints[3].name = " right"; },
          "joint 3 has an empty name or one with blanks at its ends ('\u2420right')");
  refused([](hm::BvhClip& c) { c.joints[3].name = "a\nb"; }, "joint name 'a\\nb' has a control character");
  refused([](hm::BvhClip& c) { c.joints[3].name = "right{"; }, "joint name 'right{' ends in '{'");  // (not read back)
  refused([](hm::BvhClip& c) { c.joints[2].channels = {hm::Channel::Xrotation}; }, "End Site 2 has channels");
  refused([](hm::BvhClip& c) { c.joints[1].channels.push_back(hm::Channel::Xrotation); },
          "joint 'left' lists a channel twice");
  refused([](hm::BvhClip& c) { c.values.pop_back(); }, "7 values are not a whole number of frames of 4 channels");
  refused([](hm::BvhClip& c) { c.values[5] = NAN; }, "value 2 of frame 2 is not finite");
  refused([](hm::BvhClip& c) { c.frame_time = 0; }, "the frame time must be positive");
  refused([](hm::BvhClip& c) { c.joints[1].offset.x() = INFINITY; }, "joint 'left' has a non-finite OFFSET");
}

// A CMU-like skeleton (leg and arm chains, Mixamo prefix) in one frame.
std::string skeleton(const std::string& prefix) {
  std::string s = "HIERARCHY\nROOT " + prefix +
                  "Hips\n{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition Zposition "
                  "Zrotation Yrotation Xrotation\n";
  int channels = 6;
  const auto chain = [&](const std::vector<std::pair<std::string, std::string>>& joints) {
    for (const auto& [name, offset] : joints)
      s += "JOINT " + prefix + name + "\n{\nOFFSET " + offset + "\nCHANNELS 3 Zrotation Yrotation Xrotation\n",
          channels += 3;
    s += "End Site\n{\nOFFSET 0 0 1\n}\n";
    for (std::size_t k = 0; k < joints.size(); ++k) s += "}\n";
  };
  chain({{"LeftUpLeg", "1 -1 0"}, {"LeftLeg", "0 -4 0"}, {"LeftFoot", "0 -4 0"}, {"LeftToeBase", "0 -1 1"}});
  chain({{"RightUpLeg", "-1 -1 0"}, {"RightLeg", "0 -4 0"}, {"RightFoot", "0 -4 0"}, {"RightToeBase", "0 -1 1"}});
  chain({{"Spine", "0 2 0"}, {"Neck", "0 4 0"}, {"Head", "0 1 0"}});
  chain({{"LeftArm", "2 5 0"}, {"LeftForeArm", "3 0 0"}, {"LeftHand", "3 0 0"}});
  chain({{"RightArm", "-2 5 0"}, {"RightForeArm", "-3 0 0"}, {"RightHand", "-3 0 0"}});
  s += "}\nMOTION\nFrames: 2\nFrame Time: 0.1\n";
  for (int f = 0; f < 2; ++f) {
    s += f == 0 ? "0 10 0" : "0 10 1";  // the second frame moved forward one unit
    for (int c = 3; c < channels; ++c) s += " 0";
    s += "\n";
  }
  return s;
}

TEST(Landmarks, BuiltInMapOnCmuAndMixamoNames) {
  for (const std::string prefix : {"", "mixamorig:"}) {
    SCOPED_TRACE(prefix);
    const hm::BvhClip clip = hm::parse_bvh(skeleton(prefix), "skel.bvh");
    hm::LandmarkOptions options;
    options.world = {0.1, hm::UpAxis::y};
    const hm::LandmarkClip all = hm::to_landmarks(clip, options);
    ASSERT_EQ(all.frames.size(), 2u);
    EXPECT_EQ(all.frame_time, 0.1);
    EXPECT_EQ(all.source, "skel.bvh");
    const auto& f = all.frames[0];
    const auto at = [&](hm::Landmark l) { return f[std::size_t(l)]; };
    // file (x left, y up, z forward) -> world (z, x, y), 0.1 m per unit
    EXPECT_LT((at(hm::Landmark::pelvis) - Vector3d(0, 0, 0.9)).norm(), 1e-12);
    EXPECT_LT((at(hm::Landmark::l_hip) - Vector3d(0, 0.1, 0.9)).norm(), 1e-12);
    EXPECT_LT((at(hm::Landmark::r_knee) - Vector3d(0, -0.1, 0.5)).norm(), 1e-12);
    EXPECT_LT((at(hm::Landmark::l_toe) - Vector3d(0.1, 0.1, 0)).norm(), 1e-12);
    EXPECT_LT((at(hm::Landmark::lower_back) - Vector3d(0, 0, 1.2)).norm(), 1e-12);
    EXPECT_LT((at(hm::Landmark::neck) - Vector3d(0, 0, 1.6)).norm(), 1e-12);
    EXPECT_LT((at(hm::Landmark::r_wrist) - Vector3d(0, -0.8, 1.5)).norm(), 1e-12);
    // the second frame: one unit forward
    EXPECT_LT((all.frames[1][0] - Vector3d(0.1, 0, 0.9)).norm(), 1e-12);
    options.drop_first_frame = true;
    const hm::LandmarkClip dropped = hm::to_landmarks(clip, options);
    ASSERT_EQ(dropped.frames.size(), 1u);
    EXPECT_EQ(dropped.frames[0], all.frames[1]);
    // the file's frame numbers, as the reader counts them from 1, name the frames in the fit's messages
    EXPECT_EQ(all.frame_number(0), 1);
    EXPECT_EQ(dropped.frame_number(0), 2);
    hm::LandmarkClip far = dropped;
    far.frames[0][std::size_t(hm::Landmark::l_knee)].z() = 1e300;
    try {
      hm::check_clip(far);
      ADD_FAILURE() << "a landmark at 1e300 m passed";
    } catch (const hm::MotionError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("skel.bvh: frame 2: landmark 'l_knee' lies 1e+300 m", 0), 0u) << e.what();
    }
  }
}

TEST(Landmarks, MapFileOverridesAndErrors) {
  const hm::LandmarkMap map = hm::parse_landmark_map(
      "\xEF\xBB\xBF# my skeleton\r\n  neck = Spine1  # the chest\r\npelvis=Hips\n"
      "head = Bip01 Head , Neck\n",
      "my.map");
  EXPECT_EQ(map.joints[std::size_t(hm::Landmark::neck)], std::vector<std::string>{"Spine1"});
  EXPECT_EQ(map.joints[std::size_t(hm::Landmark::pelvis)], std::vector<std::string>{"Hips"});
  EXPECT_EQ(map.joints[std::size_t(hm::Landmark::head)], (std::vector<std::string>{"Bip01 Head", "Neck"}));
  EXPECT_EQ(map.lines[std::size_t(hm::Landmark::head)], 4);
  EXPECT_EQ(map.joints[std::size_t(hm::Landmark::r_knee)], std::vector<std::string>{"RightLeg"});  // built in
  EXPECT_EQ(map.lines[std::size_t(hm::Landmark::r_knee)], 0);
  // written back, it reads the same
  const hm::LandmarkMap again = hm::parse_landmark_map(hm::to_text(map));
  EXPECT_EQ(again.joints, map.joints);

  const std::vector<std::pair<std::string, std::string>> cases{
      {"knee = LeftLeg\n", "my.map:1:1: unknown landmark 'knee' (one of pelvis, r_hip,"},
      {"\n= LeftLeg\n", "my.map:2:1: expected a landmark name before '='"},
      {"head Head\n", "my.map:1:6: expected '=' after the landmark name"},
      {"head =\n", "my.map:1:7: expected a BVH joint name"},
      {"head = Head,  \n", "my.map:1:15: expected a BVH joint name"},
      {"head = Head, # a\n", "my.map:1:14: expected a BVH joint name"},
      {"head = Head\nneck = Neck\nhead = Neck1\n", "my.map:3:1: landmark 'head' set twice (first on line 1)"},
      {"neck = Spine1, Neck,Spine1\n", "my.map:1:21: joint 'Spine1' named twice for landmark 'neck'"},
      {"head = He\x02\n", "my.map:1:10: joint name 'He<U+0002>' has a control character"},
      {"head = H\xC3\xBC\x02\n",
       "my.map:1:10: joint name 'H\xC3\xBC<U+0002>' has a control character"},  // columns count characters
      {"head = H\xC2\x85\n", "my.map:1:9: joint name 'H<U+0085>' has a control character"},
  };
  for (const auto& [text, expected] : cases) {
    SCOPED_TRACE(text);
    const std::string what = error_of([&t = text] { hm::parse_landmark_map(t, "my.map"); });
    EXPECT_EQ(what.substr(0, expected.size()), expected) << what;
  }

  // a landmark without its joint names the clip, the landmark and where it was asked for
  const hm::BvhClip clip = hm::parse_bvh(skeleton(""), "skel.bvh");
  hm::LandmarkOptions options;
  options.map = map;
  EXPECT_EQ(error_of([&] { hm::to_landmarks(clip, options); }),
            "skel.bvh: landmark 'neck': no joint 'Spine1' in the hierarchy (as my.map:2 asks; a landmark map file can "
            "name another joint)");
  options.map = hm::default_landmark_map();
  options.map.joints[std::size_t(hm::Landmark::r_toe)] = {"RightToe"};
  EXPECT_NE(error_of([&] {
              hm::to_landmarks(clip, options);
            }).find("landmark 'r_toe': no joint 'RightToe' in the hierarchy (as the built-in landmark map asks"),
            std::string::npos);
  // a built-in entry that a map file leaves as it is: the built-in map asks, not the file
  options.map = hm::parse_landmark_map("head = Head\n", "head.map");
  options.map.joints[std::size_t(hm::Landmark::r_toe)] = {"RightToe"};  // (as a built-in name the clip lacks)
  EXPECT_NE(error_of([&] { hm::to_landmarks(clip, options); })
                .find("landmark 'r_toe': no joint 'RightToe' in the hierarchy (as the built-in landmark map asks, "
                      "which head.map does not change;"),
            std::string::npos);
  // a name that two prefixed joints end in: both named, with their lines
  {
    std::string text = skeleton("a:");
    text.replace(text.find("JOINT a:Head"), 12, "JOINT b:Neck");
    options.map = hm::parse_landmark_map("head = b:Neck\n", "head.map");
    const std::string what = error_of([&] { hm::to_landmarks(hm::parse_bvh(text, "two.bvh"), options); });
    EXPECT_NE(what.find("landmark 'neck': 2 joints named '<prefix>:Neck', 'a:Neck' on line 58 and 'b:Neck' on line "
                        "62 (as the built-in landmark map asks, which head.map does not change;"),
              std::string::npos)
        << what;
    // a clip built in code has no lines to name
    hm::BvhClip built = hm::parse_bvh(text, "two.bvh");
    for (hm::BvhJoint& j : built.joints) j.line = 0;
    EXPECT_NE(error_of([&] {
                hm::to_landmarks(built, options);
              }).find("landmark 'neck': 2 joints named '<prefix>:Neck', 'a:Neck' and 'b:Neck' (as"),
              std::string::npos);
  }
  // two landmarks on one joint would make a segment of length 0: the map's line names both
  options.map = hm::parse_landmark_map("r_ankle = RightLeg\n", "same.map");
  EXPECT_EQ(error_of([&] { hm::to_landmarks(clip, options); }),
            "same.map:1: landmarks 'r_knee' (built in) and 'r_ankle' (line 1) both stand at BVH joint 'RightLeg': "
            "every landmark needs joints of its own");
  options.map = hm::parse_landmark_map("# two lines\nhead = Neck , Head\nneck = Head,Neck\n", "same.map");
  EXPECT_EQ(error_of([&] { hm::to_landmarks(clip, options); }),
            "same.map:3: landmarks 'head' (line 2) and 'neck' (line 3) both stand at BVH joints 'Neck, Head': "
            "every landmark needs joints of its own");
  options.map = hm::parse_landmark_map("neck = Neck, Head\n", "mean.map");  // a mean of a landmark's joint: kept
  EXPECT_NO_THROW(hm::to_landmarks(clip, options));
  options.map = hm::default_landmark_map();
  options.drop_first_frame = true;
  const hm::BvhClip one = hm::parse_bvh(
      skeleton("").replace(skeleton("").find("Frames: 2"), 9, "Frames: 1").substr(0, skeleton("").rfind("0 10 1")));
  EXPECT_NE(error_of([&] { hm::to_landmarks(one, options); }).find("no frame left (1 frames, the first dropped)"),
            std::string::npos);
  EXPECT_EQ(hm::landmark_names[std::size_t(hm::Landmark::l_wrist)], "l_wrist");
  EXPECT_EQ(hm::landmark_named("lower_back"), hm::Landmark::lower_back);
  EXPECT_EQ(hm::landmark_named("count"), std::nullopt);
}

// The fuzzer's seed corpora, replayed as the fuzz targets read them: each gives a result or a BvhError.
TEST(BvhFuzz, SeedCorpora) {
  int n = 0;
  for (const auto& [corpus, run] :
       {std::pair{"bvh", &humandyn::fuzz::bvh_input}, std::pair{"landmark_map", &humandyn::fuzz::landmark_map_input}}) {
    for (const auto& f : std::filesystem::directory_iterator(std::filesystem::path(HUMANDYN_FUZZ_TEST_DATA) / corpus)) {
      SCOPED_TRACE(f.path().string());
      std::ifstream in(f.path(), std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      try {
        run(text.str());
      } catch (const hm::BvhError&) {
      }
      ++n;
    }
  }
  EXPECT_GE(n, 6);
}

// The CMU clips (../shared/data/mocap, README.md there): what the README states, measured here.
struct CmuClip {
  const char* file;
  int frames;
  // the root's horizontal travel from the first captured frame to the last (m), and that over (Frames - 1) frame
  // times (m/s), as the README gives them (NaN: not given)
  double distance, speed;
};

class CmuClips : public ::testing::TestWithParam<CmuClip> {};

TEST_P(CmuClips, AsTheReadmeStates) {
  const CmuClip& c = GetParam();
  const std::filesystem::path path = std::filesystem::path(HUMANDYN_SHARED_DATA) / "mocap" / c.file;
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent: the CMU clips are not checked";
  const hm::BvhClip clip = hm::read_bvh_file(path.string());
  EXPECT_EQ(clip.frame_count(), c.frames);
  EXPECT_EQ(clip.frame_time, 0.0083333);
  EXPECT_EQ(clip.joints.size(), 31u + 7u);  // 31 joints, 7 End Sites
  EXPECT_EQ(clip.channel_count(), 96);

  const hm::WorldOptions world{hm::cmu_metres_per_unit, hm::UpAxis::y};
  const auto positions = hm::all_joint_positions(clip, world);
  // the root's travel over the captured frames (frame 1 is the added T-pose)
  const Vector3d from = positions[1][0], to = positions.back()[0];
  const double distance = (to - from).head<2>().norm();
  const double duration = (clip.frame_count() - 1) * clip.frame_time;
  EXPECT_NEAR(distance, c.distance, 0.005);  // the README's numbers, to their last digit
  if (!std::isnan(c.speed)) {
    EXPECT_NEAR(distance / duration, c.speed, 0.005);
  }

  // the feet on the floor: z up, the floor at z = 0 (the README: the lowest foot or toe joint between -0.01 and
  // 0.04 m over the clip, its median over the frames 0 to 0.055 m; to their last digit)
  std::vector<double> lowest;
  for (std::size_t f = 1; f < positions.size(); ++f) {
    double z = INFINITY;
    for (const char* name : {"LeftFoot", "RightFoot", "LeftToeBase", "RightToeBase"})
      z = std::min(z, positions[f][std::size_t(clip.find(name))].z());
    lowest.push_back(z);
  }
  EXPECT_GE(*std::min_element(lowest.begin(), lowest.end()), -0.015);
  EXPECT_LE(*std::min_element(lowest.begin(), lowest.end()), 0.045);
  std::nth_element(lowest.begin(), lowest.begin() + long(lowest.size() / 2), lowest.end());
  EXPECT_GE(lowest[lowest.size() / 2], -0.0005);
  EXPECT_LE(lowest[lowest.size() / 2], 0.0555);

  // rigid bones: every joint stays at its OFFSET's length from its parent, in every frame
  for (std::size_t j = 1; j < clip.joints.size(); ++j) {
    const double length = hm::to_world(clip.joints[j].offset, world).norm();
    const auto parent = std::size_t(clip.joints[j].parent);
    double worst = 0;
    for (const auto& p : positions) worst = std::max(worst, std::abs((p[j] - p[parent]).norm() - length));
    EXPECT_LT(worst, 1e-12) << clip.joints[j].name;
  }

  // landmarks: the T-pose dropped, every landmark finite
  hm::LandmarkOptions options;
  options.world = world;
  options.drop_first_frame = true;
  const hm::LandmarkClip landmarks = hm::to_landmarks(clip, options);
  ASSERT_EQ(landmarks.frames.size(), std::size_t(c.frames - 1));
  for (const auto& frame : landmarks.frames)
    for (const auto& p : frame) ASSERT_TRUE(p.allFinite());
  // the thigh: 0.39-0.43 m in every clip
  const auto& f0 = landmarks.frames[0];
  const double thigh = (f0[std::size_t(hm::Landmark::l_knee)] - f0[std::size_t(hm::Landmark::l_hip)]).norm();
  EXPECT_GT(thigh, 0.38);
  EXPECT_LT(thigh, 0.44);

  // frame 1, the added T-pose: whole-number rotations as the README lists them, the root where frame 2 has it
  const auto value = [&](int frame, const char* joint, hm::Channel channel) {
    int index = 0;
    for (const auto& j : clip.joints)
      for (const hm::Channel listed : j.channels) {
        if (j.name == joint && listed == channel) return clip.values[std::size_t(frame * clip.channel_count() + index)];
        ++index;
      }
    ADD_FAILURE() << joint << " has no such channel";
    return double(NAN);
  };
  using C = hm::Channel;
  EXPECT_EQ(value(0, "LeftUpLeg", C::Zrotation), -21);
  EXPECT_EQ(value(0, "RightUpLeg", C::Zrotation), 21);
  EXPECT_EQ(value(0, "Neck", C::Xrotation), -16);
  EXPECT_EQ(value(0, "Neck1", C::Xrotation), 21);
  EXPECT_EQ(value(0, "Head", C::Xrotation), 11);
  EXPECT_EQ(value(0, "LeftArm", C::Zrotation), -8);
  EXPECT_EQ(value(0, "RightArm", C::Zrotation), 8);
  EXPECT_EQ(value(0, "LeftLeg", C::Xrotation), 0);
  for (const C axis : {C::Xposition, C::Yposition, C::Zposition})
    EXPECT_EQ(value(0, "Hips", axis), value(1, "Hips", axis));

  // written and read back: the same clip
  const hm::BvhClip back = hm::parse_bvh(hm::to_bvh(clip), "back.bvh");
  EXPECT_EQ(back.values, clip.values);
  EXPECT_EQ(back.frame_time, clip.frame_time);
}

// The jump (02_04): the root from 0.73 m (crouch) to 1.47 m (in the air), both feet up to 0.48 m off the floor.
TEST(CmuJump, HeightsAsTheReadmeStates) {
  const std::filesystem::path path = std::filesystem::path(HUMANDYN_SHARED_DATA) / "mocap" / "02_04.bvh";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent: the CMU clips are not checked";
  const hm::BvhClip clip = hm::read_bvh_file(path.string());
  const auto positions = hm::all_joint_positions(clip, {hm::cmu_metres_per_unit, hm::UpAxis::y});
  double root_low = INFINITY, root_high = -INFINITY, feet_high = -INFINITY;
  for (std::size_t f = 1; f < positions.size(); ++f) {
    root_low = std::min(root_low, positions[f][0].z());
    root_high = std::max(root_high, positions[f][0].z());
    double lowest = INFINITY;
    for (const char* name : {"LeftFoot", "RightFoot", "LeftToeBase", "RightToeBase"})
      lowest = std::min(lowest, positions[f][std::size_t(clip.find(name))].z());
    feet_high = std::max(feet_high, lowest);
  }
  EXPECT_NEAR(root_low, 0.73, 0.005);
  EXPECT_NEAR(root_high, 1.47, 0.005);
  EXPECT_NEAR(feet_high, 0.48, 0.005);
}

INSTANTIATE_TEST_SUITE_P(Mocap, CmuClips,
                         ::testing::Values(CmuClip{"07_08.bvh", 363, 4.12, 1.37}, CmuClip{"35_02.bvh", 407, 4.22, 1.25},
                                           CmuClip{"02_03.bvh", 174, 3.72, 2.58}, CmuClip{"02_04.bvh", 484, 0.05, NAN}),
                         [](const auto& p) { return "clip_" + std::string(p.param.file).substr(0, 5); });

// The fit on the four clips as `humandyn motion import --cmu` runs it (the built-in landmark map, frame 1
// dropped): each segment's residual, median and 95th percentile over the clip in degrees, the scaled
// statures and the Levenberg-Marquardt iterations per frame. docs/motion.md ("On the CMU clips") quotes the
// table this prints: `build/tests/test_bvh --gtest_filter='CmuFit.*'`. (The sanitizer build fits the first
// clip alone: the four take minutes at -O0.)
TEST(CmuFit, ResidualsPerSegment) {
  const std::filesystem::path dir = std::filesystem::path(HUMANDYN_SHARED_DATA) / "mocap";
  if (!std::filesystem::exists(dir / "07_08.bvh")) GTEST_SKIP() << dir << " is absent: the CMU clips are not fitted";
  std::vector<std::string> names{"07_08", "35_02", "02_03", "02_04"};
  if (humandyn::testing::short_runs) names.resize(1);
  std::vector<std::string> rows(hm::num_fit_segments);
  std::string statures, iterations;
  const auto printed = [](const char* format, auto... values) {
    char text[256];
    std::snprintf(text, sizeof text, format, values...);
    return std::string(text);
  };
  for (const std::string& name : names) {
    hm::LandmarkOptions lo;
    lo.world = {hm::cmu_metres_per_unit, hm::UpAxis::y};
    lo.drop_first_frame = true;
    const hm::ImportedClip m =
        hm::import_clip(hm::to_landmarks(hm::read_bvh_file((dir / (name + ".bvh")).string()), lo));
    const std::size_t n = m.fit.frames.size();
    ASSERT_GT(n, 100u);
    const auto quantile = [n](std::vector<double> v, double share) {
      std::sort(v.begin(), v.end());
      return v[std::size_t(share * double(n - 1))];
    };
    for (int k = 0; k < hm::num_fit_segments; ++k) {
      std::vector<double> r;
      for (const auto& f : m.fit.frames) r.push_back(f.residual[std::size_t(k)]);
      const double median = quantile(r, 0.5), p95 = quantile(r, 0.95);
      rows[std::size_t(k)] += printed(" %.1f / %.1f |", median, p95);
      EXPECT_LE(median, 20.0) << name << " " << hm::fit_segments[std::size_t(k)].name;
      EXPECT_LE(p95, 30.0) << name << " " << hm::fit_segments[std::size_t(k)].name;
      if (k == int(hm::FitSegment::pelvis) || k == int(hm::FitSegment::trunk)) {
        EXPECT_LE(median, 3.0) << name;
      }
    }
    std::vector<double> it;
    for (const auto& f : m.fit.frames) it.push_back(f.iterations);
    iterations += printed("%s%s: median %g, max %g", iterations.empty() ? "" : "; ", name.c_str(), quantile(it, 0.5),
                          quantile(it, 1.0));
    statures += printed("%s%s: %.2f m", statures.empty() ? "" : "; ", name.c_str(), m.body.stature);
    EXPECT_GT(m.body.stature, 1.5);
    EXPECT_LT(m.body.stature, 1.9);
  }
  std::string table = "| segment | `07_08` walk | `35_02` walk | `02_03` jog | `02_04` jump |\n|---|---|---|---|---|\n";
  for (int k = 0; k < hm::num_fit_segments; ++k)
    table += std::string("| `") + hm::fit_segments[std::size_t(k)].name + "` |" + rows[std::size_t(k)] + "\n";
  std::printf("%s\nstatures: %s\niterations per frame: %s\n", table.c_str(), statures.c_str(), iterations.c_str());
}

}  // namespace

}  // namespace test_bvh
