// `humandyn motion import` end to end: a motion known in closed form written as a BVH clip, imported, and
// run through `humandyn id`; a real CMU walk's ground reaction with and without the stance foot's motion;
// a folder of clips with a bad one among them.
#include "cli/base_columns.hpp"
#include "cli/csv.hpp"
#include "cli/model_json.hpp"
#include "humandyn/anatomy.hpp"
#include "humandyn/bvh.hpp"
#include "humandyn/humandyn.hpp"
#include "humandyn/motion/import.hpp"
#include "support/cli_run.hpp"
#include "support/floating_motion.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace test_motion_cli {

namespace {

using namespace humandyn;
using namespace humandyn::motion;
using humandyn::testing::CliRun;
using humandyn::testing::humandyn_cli;
using humandyn::testing::read_text;
using humandyn::testing::Scratch;
using humandyn::testing::write_text;

// The landmarks as a BVH clip written independently of `motion export` (metres, Z up): a root `Hips` at the mid-hip
// point and, under it, one joint per landmark named as the built-in map reads it, each with position channels only.
std::string landmarks_bvh(const LandmarkClip& clip) {
  const std::vector<std::pair<Landmark, const char*>> names{{Landmark::r_hip, "RightUpLeg"},
                                                            {Landmark::r_knee, "RightLeg"},
                                                            {Landmark::r_ankle, "RightFoot"},
                                                            {Landmark::r_toe, "RightToeBase"},
                                                            {Landmark::l_hip, "LeftUpLeg"},
                                                            {Landmark::l_knee, "LeftLeg"},
                                                            {Landmark::l_ankle, "LeftFoot"},
                                                            {Landmark::l_toe, "LeftToeBase"},
                                                            {Landmark::lower_back, "Spine"},
                                                            {Landmark::neck, "Neck"},
                                                            {Landmark::head, "Head"},
                                                            {Landmark::r_shoulder, "RightArm"},
                                                            {Landmark::r_elbow, "RightForeArm"},
                                                            {Landmark::r_wrist, "RightHand"},
                                                            {Landmark::l_shoulder, "LeftArm"},
                                                            {Landmark::l_elbow, "LeftForeArm"},
                                                            {Landmark::l_wrist, "LeftHand"}};
  const std::vector<Channel> xyz{Channel::Xposition, Channel::Yposition, Channel::Zposition};
  BvhClip b;
  b.frame_time = clip.frame_time;
  b.joints.push_back({"Hips", -1, Eigen::Vector3d::Zero(), xyz});
  for (const auto& n : names) b.joints.push_back({n.second, 0, Eigen::Vector3d::Zero(), xyz});
  for (const LandmarkFrame& f : clip.frames) {
    const Eigen::Vector3d mid = 0.5 * (f[int(Landmark::r_hip)] + f[int(Landmark::l_hip)]);
    b.values.insert(b.values.end(), mid.data(), mid.data() + 3);
    for (const auto& n : names) {
      const Eigen::Vector3d d = f[int(n.first)] - mid;
      b.values.insert(b.values.end(), d.data(), d.data() + 3);
    }
  }
  return to_bvh(b);
}

// A column of a CSV table by name (the test fails if it is missing).
std::vector<double> column(const cli::CsvTable& t, const std::string& name) {
  const int c = t.column(name);
  EXPECT_GE(c, 0) << name;
  std::vector<double> v;
  for (const auto& r : t.rows) v.push_back(c < 0 ? NAN : r[std::size_t(c)]);
  return v;
}

std::string fmt_g(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", x);
  return b;
}

// The phase column, and the stance column where there is one (id reads it), kept as text.
void keep_text(cli::CsvTable& t) {
  t.keep_as_text(t.require_column("phase"));
  if (t.column("stance") >= 0) t.keep_as_text(t.column("stance"));
}

ClipBody source_body() { return humandyn::testing::closed_loop_body(); }

// The first 60 frames of the turning walk as the source body's landmarks, frame_time apart.
LandmarkClip short_walk(double frame_time) {
  const Fitter source(source_body());
  LandmarkClip clip;
  clip.frame_time = frame_time;
  for (int k = 0; k < 60; ++k) {
    const FloatingFrame f = humandyn::testing::turning_walk(source.model(), k * frame_time);
    clip.frames.push_back(source.landmarks(f.base, f.q));
  }
  return clip;
}

// The largest difference (rad, modulo a turn) between the anatomical angles of two states files of as many
// rows; infinite when the row counts differ.
double worst_angle_difference(const std::filesystem::path& a, const std::filesystem::path& b) {
  const cli::CsvTable x = cli::read_csv(a.string(), keep_text), y = cli::read_csv(b.string(), keep_text);
  if (x.rows.size() != y.rows.size()) return std::numeric_limits<double>::infinity();
  double worst = 0;
  for (const auto& joint : anatomical_joints) {
    const std::vector<double> u = column(x, joint.name), v = column(y, joint.name);
    for (std::size_t k = 0; k < u.size(); ++k) worst = std::max(worst, std::abs(std::remainder(u[k] - v[k], 2 * M_PI)));
  }
  return worst;
}

TEST(MotionCli, ClosedLoopAnglesAndTorques) {
  // the known motion as a BVH clip: imported unfiltered, its anatomical angles are the exact ones to
  // 1e-6 rad; imported at 6 Hz and run through `id` with the stance foot's motion, its torques are those of
  // the exact states run through the same `id` to what the filter explains (1e-3 of the largest torque)
  const Scratch dir;
  const Fitter source(source_body());
  const double h = 1.0 / 120, T = 4.0;
  LandmarkClip clip;
  clip.frame_time = h;
  std::vector<FloatingFrame> frames;
  for (int k = 0; k * h <= T; ++k) {
    frames.push_back(humandyn::testing::turning_walk(source.model(), k * h));
    clip.frames.push_back(source.landmarks(frames.back().base, frames.back().q));
  }
  write_text(dir / "clip.bvh", landmarks_bvh(clip));

  CliRun r = humandyn_cli(dir, "motion import clip.bvh --up z --cutoff 0 --out raw.csv --model-out body.json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // one warning: the turning walk's feet never stand still, so the toe's drop is not measured (the source
  // body's toe lies on the sole, as the import then takes it)
  EXPECT_EQ(r.err.rfind("warning"),
            r.err.find("warning: clip.bvh: a foot is still (its ankle slower than 0.5 m/s, "
                       "its toe than 0.3 m/s) 0 time(s) over the frames of both feet, fewer than 10: the toe is "
                       "taken to lie on the sole"))
      << r.err;
  // with the body given, its toe's drop is the body's: the warning is of the contact phases alone
  const CliRun given = humandyn_cli(dir, "motion import clip.bvh --up z --cutoff 0 --model body.json --out given.csv");
  ASSERT_EQ(given.exit_code, 0) << given.err;
  EXPECT_EQ(given.err.rfind("warning"),
            given.err.find("warning: clip.bvh: a foot is still (its ankle slower than 0.5 m/s, its toe than 0.3 m/s) "
                           "0 time(s) over the frames of both feet, fewer than 10: the contact phases, found from "
                           "the feet's speed, may read flight where a foot is down (a treadmill, or walking in "
                           "place?)\n"))
      << given.err;
  // read in another unit, or on its side, the clip still fits; the import says what looks wrong
  const CliRun giant = humandyn_cli(dir, "motion import clip.bvh --up z --unit 20 --out giant.csv");
  EXPECT_NE(giant.err.find("warning: clip.bvh: the body scaled to it stands "), std::string::npos) << giant.err;
  EXPECT_NE(giant.err.find(" m tall, outside a person's 0.5 to 2.5 m: is the file's unit 20 m (--unit; --cmu for "
                           "CMU's clips)?"),
            std::string::npos)
      << giant.err;
  const CliRun side = humandyn_cli(dir, "motion import clip.bvh --up y --out side.csv");
  EXPECT_NE(side.err.find("warning: clip.bvh: the head is above both ankles in "), std::string::npos) << side.err;
  EXPECT_NE(side.err.find(" frames: is the file's up axis y (--up)?"), std::string::npos) << side.err;
  const cli::CsvTable raw = cli::read_csv((dir / "raw.csv").string(), keep_text);
  ASSERT_EQ(raw.rows.size(), frames.size());
  double worst_angle = 0;
  for (int j = 0; j < 16; ++j) {
    const std::vector<double> fitted = column(raw, anatomical_joints[std::size_t(j)].name);
    for (std::size_t k = 0; k < frames.size(); ++k) {
      std::array<double, 16> a{};
      anatomical_angles(BodyForm::Floating, frames[k].q, a);
      worst_angle = std::max(worst_angle, std::abs(std::remainder(fitted[k] - a[std::size_t(j)], 2 * M_PI)));
    }
  }
  EXPECT_LT(worst_angle, 1e-6) << "rad";
  RecordProperty("worst_angle_rad", fmt_g(worst_angle));

  // the exact states in the same columns, each row on the stance foot the import chose
  r = humandyn_cli(dir, "motion import clip.bvh --up z --mass 73 --out states.csv --model-out body.json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // `humandyn model` keeps the body file's landmarks in its JSON, and says that a URDF cannot carry them
  {
    const cli::json::Json file = cli::json::read_file((dir / "body.json").string());
    ASSERT_TRUE(file.contains("landmarks"));
    const CliRun printed = humandyn_cli(dir, "model --model body.json --json");
    ASSERT_EQ(printed.exit_code, 0) << printed.err;
    EXPECT_EQ(cli::json::parse(printed.out, "printed").at("landmarks"), file.at("landmarks"));
    EXPECT_EQ(cli::parse_model_json(printed.out, "printed").joints.size(), 16U);
    const CliRun urdf = humandyn_cli(dir, "model --model body.json --urdf body.urdf");
    ASSERT_EQ(urdf.exit_code, 0) << urdf.err;
    EXPECT_NE(urdf.err.find("humandyn model: warning: body.json's \"landmarks\" are not in body.urdf"),
              std::string::npos)
        << urdf.err;
    // nor the base's pose and gravity: how to read it back is said
    EXPECT_NE(urdf.err.find("humandyn model: warning: body.urdf has no place for the gravity or the base pose of "
                            "'body.json': gravity in its base link's frame, (-9.81, 0, 0) m/s^2, is in its first "
                            "comment; read it back with --up x to keep it; the base's position in the world, ("),
              std::string::npos)
        << urdf.err;
    // read back so, the base at the world's origin: written again, only the gravity it still needs is said
    const CliRun again = humandyn_cli(dir, "model --model body.urdf --up x --urdf again.urdf");
    ASSERT_EQ(again.exit_code, 0) << again.err;
    EXPECT_EQ(again.err,
              "humandyn model: warning: again.urdf has no place for the gravity or the base pose of 'body.urdf': "
              "gravity in its base link's frame, (-9.81, 0, 0) m/s^2, is in its first comment; read it back with "
              "--up x to keep it\n");
    // a model whose world is its base link's frame, gravity down its z (a URDF read without --up): nothing
    // to say
    const CliRun upright = humandyn_cli(dir, "model --model again.urdf --urdf upright.urdf");
    ASSERT_EQ(upright.exit_code, 0) << upright.err;
    EXPECT_EQ(upright.err, "");
    const CliRun itself = humandyn_cli(dir, "model --model body.json --urdf ./body.json");
    EXPECT_EQ(itself.exit_code, 2) << itself.err;
    EXPECT_NE(itself.err.find("./body.json is given to --model and --urdf"), std::string::npos) << itself.err;
    EXPECT_EQ(cli::json::read_file((dir / "body.json").string()), file);

    // the same body turned in its file (its base pose yawed), and written as a URDF (which the importer
    // lays on its side: z along the ankle axis): the same fit, angle for angle
    cli::json::Json turned = file, bare = file;
    cli::json::Json& R = turned.at("base").at("pose").at("R");
    const cli::json::Json R0 = R;
    for (std::size_t j = 0; j < 3; ++j) {
      const double x = R0[0][j], y = R0[1][j];
      R[0][j] = std::cos(0.7) * x - std::sin(0.7) * y;
      R[1][j] = std::sin(0.7) * x + std::cos(0.7) * y;
    }
    bare.erase("landmarks");
    write_text(dir / "turned.json", cli::json::write(turned));
    write_text(dir / "bare.json", cli::json::write(bare));
    // a URDF of the turned body keeps its gravity (--up x) but not its heading, which is said
    const CliRun turned_urdf = humandyn_cli(dir, "model --model turned.json --urdf turned.urdf");
    ASSERT_EQ(turned_urdf.exit_code, 0) << turned_urdf.err;
    EXPECT_NE(turned_urdf.err.find("read it back with --up x to keep it; the base's position in the world, ("),
              std::string::npos)
        << turned_urdf.err;
    EXPECT_NE(turned_urdf.err.find(") m, is not kept: read back, its origin is the world's; the base's orientation "
                                   "in the world is not kept: read back, the world's axes are built from gravity "
                                   "alone (z against it)\n"),
              std::string::npos)
        << turned_urdf.err;
    std::vector<std::vector<double>> fits[4];
    const char* models[] = {"body.json", "turned.json", "bare.json", "body.urdf"};
    for (std::size_t m = 0; m < 4; ++m) {
      const CliRun fit =
          humandyn_cli(dir, std::string("motion import clip.bvh --up z --cutoff 0 --out fit.csv --model ") + models[m]);
      ASSERT_EQ(fit.exit_code, 0) << models[m] << ": " << fit.err;
      const cli::CsvTable t = cli::read_csv((dir / "fit.csv").string(), keep_text);
      for (const auto& joint : anatomical_joints) fits[m].push_back(column(t, joint.name));
    }
    const auto worst = [&](std::size_t a, std::size_t b) {
      double w = 0;
      for (std::size_t j = 0; j < fits[a].size(); ++j)
        for (std::size_t k = 0; k < fits[a][j].size(); ++k) w = std::max(w, std::abs(fits[a][j][k] - fits[b][j][k]));
      return w;
    };
    EXPECT_LE(worst(0, 1), 1e-9) << "rad, the turned body file";
    EXPECT_LE(worst(2, 3), 1e-9) << "rad, the body's URDF";
    // a FILE.urdf takes the importer's --root (a link it lacks: an error naming it), --joints and
    // --balance-inertia; they go with a URDF only
    {
      const CliRun root =
          humandyn_cli(dir, "motion import clip.bvh --up z --out fit.csv --model body.urdf --root nosuch");
      EXPECT_EQ(root.exit_code, 1) << root.err;
      EXPECT_NE(root.err.find("'nosuch'"), std::string::npos) << root.err;
      const CliRun json =
          humandyn_cli(dir, "motion import clip.bvh --up z --out fit.csv --model body.json --root base");
      EXPECT_EQ(json.exit_code, 2);
      EXPECT_NE(json.err.find("the URDF importer's options (--root, --joints, the up axis, --gravity, "
                              "--balance-inertia) go with --model FILE.urdf"),
                std::string::npos)
          << json.err;
    }

    // the body --model-out writes is the standing one the states were fitted with
    ASSERT_EQ(humandyn_cli(dir,
                           "motion import clip.bvh --up z --cutoff 0 --model turned.json --out fit.csv "
                           "--model-out turned_out.json")
                  .exit_code,
              0);
    const cli::json::Json written = cli::json::read_file((dir / "turned_out.json").string());
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_NEAR(double(written.at("base").at("pose").at("p")[i]), double(file.at("base").at("pose").at("p")[i]),
                  1e-12);
      for (std::size_t j = 0; j < 3; ++j)
        EXPECT_NEAR(double(written.at("base").at("pose").at("R")[i][j]),
                    double(file.at("base").at("pose").at("R")[i][j]), 1e-12);
    }
    // motion export of rows without the foot's pose stands the body where its file's base pose puts it
    cli::json::Json shifted = file;
    shifted["base"]["pose"]["p"][0] = double(file.at("base").at("pose").at("p")[0]) + 1.0;
    write_text(dir / "shifted.json", cli::json::write(shifted));
    std::string rest = "t";
    for (const auto& j : cli::parse_model_json(printed.out, "printed").joints) rest += ",q_" + j.name;
    for (const char* t : {"0", "0.01"}) {
      rest += std::string("\n") + t;
      for (int j = 0; j < 16; ++j) rest += ",0.1";
    }
    write_text(dir / "rest.csv", rest + "\n");
    BvhClip at[2];
    for (std::size_t m = 0; m < 2; ++m) {
      const std::string model = m == 0 ? "body.json" : "shifted.json";
      const CliRun e = humandyn_cli(dir, "motion export rest.csv --model " + model + " --out rest.bvh");
      ASSERT_EQ(e.exit_code, 0) << model << ": " << e.err;
      at[m] = read_bvh_file((dir / "rest.bvh").string());
    }
    ASSERT_EQ(at[0].values.size(), at[1].values.size());
    const int cc = at[0].channel_count();
    for (int f = 0; f < 2; ++f) {
      const auto k = std::size_t(f * cc);
      const Eigen::Vector3d a(at[0].values[k], at[0].values[k + 1], at[0].values[k + 2]),
          b(at[1].values[k], at[1].values[k + 1], at[1].values[k + 2]);
      EXPECT_NEAR((b - a).norm(), 1.0, 1e-9) << "the root moved with the file's base, frame " << f;
      for (std::size_t c = 3; c < std::size_t(cc); ++c)
        EXPECT_NEAR(at[0].values[k + c], at[1].values[k + c], 1e-9) << "channel " << c << ", frame " << f;
    }
  }
  const cli::CsvTable filtered = cli::read_csv((dir / "states.csv").string(), keep_text);
  const StanceForms forms(default_parameters());
  std::string text;
  for (std::size_t c = 0; c < filtered.header.size(); ++c) text += (c ? "," : "") + filtered.header[c];
  text += "\n";
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const bool left = filtered.text(k, filtered.column("stance")) == "left";
    StanceFrame s, right;
    forms.stance_state(left ? Foot::left : Foot::right, frames[k], s);
    forms.stance_state(Foot::right, frames[k], right);
    text += cli::format_number(double(k) * h) + ",flight," + (left ? "left" : "right");
    for (const double v : cli::stance_state_values(s.base, right.q, right.qd, right.qdd))
      text += "," + cli::format_number(v);
    for (std::size_t i = 0; i < 16; ++i) text += ",0";
    text += "\n";
  }
  write_text(dir / "exact.csv", text);
  r = humandyn_cli(dir, "id --model body.json --in states.csv --out tau.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = humandyn_cli(dir, "id --in exact.csv --out tau_exact.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const cli::CsvTable tau = cli::read_csv((dir / "tau.csv").string(), keep_text),
                      tau_exact = cli::read_csv((dir / "tau_exact.csv").string(), keep_text);
  // the exact states written back as BVH by `motion export` and imported again: the same angles
  r = humandyn_cli(dir, "motion export exact.csv --out back.bvh");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = humandyn_cli(dir, "motion import back.bvh --cutoff 0 --out back.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const cli::CsvTable back = cli::read_csv((dir / "back.csv").string(), keep_text);
  ASSERT_EQ(back.rows.size(), frames.size());
  double worst_back = 0;
  for (int j = 0; j < 16; ++j) {
    const std::vector<double> again = column(back, anatomical_joints[std::size_t(j)].name);
    for (std::size_t k = 0; k < frames.size(); ++k) {
      std::array<double, 16> a{};
      anatomical_angles(BodyForm::Floating, frames[k].q, a);
      worst_back = std::max(worst_back, std::abs(std::remainder(again[k] - a[std::size_t(j)], 2 * M_PI)));
    }
  }
  EXPECT_LT(worst_back, 1e-6) << "rad";
  RecordProperty("worst_angle_exported_rad", fmt_g(worst_back));

  double largest = 0, worst = 0;
  for (const std::string& name : humandyn::testing::joint_names(human_description(default_parameters()))) {
    const std::vector<double> a = column(tau, "tau_" + name), e = column(tau_exact, "tau_" + name);
    for (std::size_t k = 60; k + 60 < frames.size(); ++k) {  // 0.5 s in from either end
      largest = std::max(largest, std::abs(e[k]));
      worst = std::max(worst, std::abs(a[k] - e[k]));
    }
  }
  EXPECT_GT(largest, 10.0) << "N m";
  EXPECT_LT(worst, 1e-3 * largest) << worst << " of " << largest << " N m";
  RecordProperty("worst_torque_error", fmt_g(worst / largest));
}

// motion export moves the body it is given: a clip of a body of other proportions, imported with
// --model-out, exported on that body's file and imported again gives the same angles and a body of the
// same lengths; exported on the default body, the lengths are the default's. A model file whose DH rows
// are not the seed's formula of any lengths is refused, naming the joint.
TEST(MotionCli, ExportMovesAScaledBody) {
  const Scratch dir;
  ClipBody body = source_body();
  SeedParameters& p = body.parameters;
  for (const auto& f : humandyn::detail::dimensions) p.*f.member *= 1.08;
  p.a9 = default_parameters().a9 * 0.95;
  body.toe_drop = p.a16;
  const Fitter source(body);
  const double h = 1.0 / 120;
  LandmarkClip clip;
  clip.frame_time = h;
  for (int k = 0; k * h <= 1.0; ++k) {
    const FloatingFrame f = humandyn::testing::turning_walk(source.model(), k * h);
    clip.frames.push_back(source.landmarks(f.base, f.q));
  }
  write_text(dir / "clip.bvh", landmarks_bvh(clip));
  for (const char* command : {"motion import clip.bvh --up z --cutoff 0 --out states.csv --model-out body.json",
                              "motion export states.csv --model body.json --out back.bvh",
                              "motion import back.bvh --cutoff 0 --out back.csv --model-out back.json",
                              "motion export states.csv --out default.bvh",
                              "motion import default.bvh --cutoff 0 --out default.csv --model-out default.json"}) {
    const CliRun r = humandyn_cli(dir, command);
    ASSERT_EQ(r.exit_code, 0) << command << "\n" << r.err;
  }
  const double worst = worst_angle_difference(dir / "states.csv", dir / "back.csv");
  EXPECT_LT(worst, 1e-6) << "rad";
  RecordProperty("worst_angle_rad", fmt_g(worst));
  const auto lengths = [&](const char* file) {
    return with_dimensions_of(cli::read_model_json((dir / file).string()), default_parameters());
  };
  const SeedParameters imported = lengths("body.json"), again = lengths("back.json"), plain = lengths("default.json");
  for (const auto& f : humandyn::detail::dimensions) {
    EXPECT_NEAR(again.*f.member, imported.*f.member, 1e-9) << f.name;
    EXPECT_NEAR(plain.*f.member, default_parameters().*f.member, 1e-9) << f.name;
  }
  EXPECT_GT(std::abs(imported.a1 - default_parameters().a1), 0.01);

  // a model file of another shape: refused, naming the joint
  ModelDescription<double> edited = human_description(p);
  edited.joints[14].dh.a += 0.02;  // the left shank's a1 against the right's
  write_text(dir / "edited.json", cli::write_model_json(edited));
  const CliRun r = humandyn_cli(dir, "motion export states.csv --model edited.json --out edited.bvh");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("joint 15 'l_knee_pitch': its DH a gives a1"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "edited.bvh"));
  // the floating form, --mass beside a given body, an empty --model, one file for both outputs, landmarks
  // beyond the body's size or not an object: refused, saying why
  write_text(dir / "floating.json", humandyn_cli(dir, "model --json --floating").out);
  cli::json::Json big = cli::json::read_file((dir / "body.json").string()), list = big;
  big["landmarks"]["foot_length"] = 10.0;
  list["landmarks"] = cli::json::Json::array({1, 2, 3, 4});
  write_text(dir / "big_foot.json", cli::json::write(big));
  write_text(dir / "list.json", cli::json::write(list));
  const std::pair<std::string, std::string> refusals[] = {
      {"motion export states.csv --model floating.json --out f.bvh", "describes the floating form of a body"},
      {"motion import clip.bvh --up z --model body.json --mass 60 --out m.csv", "--model does not go with --mass"},
      {"motion import clip.bvh --up z --model '' --out m.csv", "--model is given an empty value"},
      {"motion import clip.bvh --up z --out - --model-out -",
       "--out - and --model-out -: standard output takes one of them; give the other a file"},
      {"motion import clip.bvh --up z --out /dev/stdout --model-out -",  // however standard output is named
       "--out /dev/stdout and --model-out -: standard output takes one of them; give the other a file"},
      {"motion import clip.bvh --up z --out same.csv --model-out same.csv",
       "same.csv is given to --out and --model-out"},
      {"motion export states.csv --model big_foot.json --out b.bvh", "/landmarks/foot_length: 10 m is outside"},
      {"id --model list.json --in states.csv --out tau.csv", "/landmarks"}};
  // a time step that changes between rows (a BVH clip has one frame time): refused, naming the row
  std::string uneven = read_text(dir / "states.csv");
  const std::size_t row6 = [&] {
    std::size_t at = 0;
    for (int line = 0; line < 6; ++line) at = uneven.find('\n', at) + 1;
    return at;
  }();
  uneven.replace(row6, uneven.find(',', row6) - row6, "0.5");  // t of the sixth row
  write_text(dir / "uneven.csv", uneven);
  const CliRun bad_t = humandyn_cli(dir, "motion export uneven.csv --model body.json --out u.bvh");
  EXPECT_NE(bad_t.exit_code, 0);
  EXPECT_NE(bad_t.err.find("the time step is"), std::string::npos) << bad_t.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "u.bvh"));
  // times near double's ends: a first step beyond its range, named at its row (once a message naming no file)
  std::string far = read_text(dir / "states.csv");
  const std::size_t row1 = far.find('\n') + 1, row2 = far.find('\n', row1) + 1;
  far.replace(row2, far.find(',', row2) - row2, "1.7e308");
  far.replace(row1, far.find(',', row1) - row1, "-1.7e308");
  write_text(dir / "far.csv", far);
  const CliRun far_t = humandyn_cli(dir, "motion export far.csv --model body.json --out f.bvh");
  EXPECT_EQ(far_t.exit_code, 1);
  EXPECT_NE(far_t.err.find("far.csv: line 3, column 1 't': the time step from the first row, -1.7e+308 s, is beyond "
                           "double's range"),
            std::string::npos)
      << far_t.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "f.bvh"));
  // no t column: no frame time to give the clip, refused (no default is guessed)
  std::string no_t;
  for (std::size_t at = 0; at < uneven.size();) {
    const std::size_t end = uneven.find('\n', at);
    no_t += uneven.substr(uneven.find(',', at) + 1, end - uneven.find(',', at));
    at = end + 1;
  }
  write_text(dir / "no_t.csv", no_t);
  const CliRun untimed = humandyn_cli(dir, "motion export no_t.csv --model body.json --out n.bvh");
  EXPECT_NE(untimed.exit_code, 0);
  EXPECT_NE(untimed.err.find("'t'"), std::string::npos) << untimed.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "n.bvh"));
  for (const auto& [command, want] : refusals) {
    const CliRun run = humandyn_cli(dir, command);
    EXPECT_NE(run.exit_code, 0) << command;
    EXPECT_NE(run.err.find(want), std::string::npos) << command << "\n" << run.err;
  }
}

// A real walk (07_08: moving stance feet, the foot's shape measured from the clip) through `--model-out` and
// `motion export --model`, imported again with `--model` (the same body, not one scaled anew): every
// anatomical angle comes back, and the body file too, byte for byte. Without --model, or with a built-in
// body, the ankles turn.
// export reads a states file as id and view read it: the stance column without base columns holds the
// stance foot still (the left foot on left rows, as view shows it), a stance that is no foot and a misspelt
// column are errors naming them, and each base group is all or none
TEST(MotionCli, ExportReadsTheStatesAsViewDoes) {
  const Scratch dir;
  const std::vector<std::string> names = humandyn::testing::joint_names(human_description(default_parameters()));
  std::string header = "t";
  for (const auto& n : names) header += ",q_" + n;
  const auto rows = [&](const std::string& extra_header, const std::vector<std::string>& extra) {
    std::string text = header + extra_header + "\n";
    for (std::size_t r = 0; r < extra.size(); ++r) {
      text += cli::format_number(0.01 * double(r));
      for (std::size_t j = 0; j < names.size(); ++j)  // the right leg bends on the last two rows
        text += r >= 2 && (names[j] == "r_ankle_pitch" || names[j] == "r_hip_pitch") ? ",0.2"
                : r >= 2 && names[j] == "r_knee_pitch"                               ? ",-0.4"
                                                                                     : ",0";
      text += extra[r] + "\n";
    }
    return text;
  };
  write_text(dir / "switch.csv", rows(",stance", {",right", ",left", ",left", ",left"}));
  CliRun r = humandyn_cli(dir, "motion export switch.csv --out switch.bvh");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BvhClip clip = parse_bvh(read_text(dir / "switch.bvh"), "switch.bvh");
  const int left_foot = clip.find("LeftFoot"), right_foot = clip.find("RightFoot");
  ASSERT_GE(left_foot, 0);
  const auto at = [&](int frame, int joint) { return joint_positions(clip, frame)[std::size_t(joint)]; };
  for (int frame : {2, 3}) EXPECT_LE((at(frame, left_foot) - at(1, left_foot)).norm(), 1e-9) << frame;
  EXPECT_GT((at(3, right_foot) - at(1, right_foot)).norm(), 0.01);  // the right foot lifted

  write_text(dir / "middle.csv", rows(",stance", {",right", ",middle", ",left", ",left"}));
  r = humandyn_cli(dir, "motion export middle.csv --out middle.bvh");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("middle.csv: line 3, column 18 'stance': 'middle' is not a stance foot"), std::string::npos)
      << r.err;
  write_text(dir / "typo.csv", rows(",qd_r_knee_pitchh", {",1", ",1", ",1", ",1"}));
  r = humandyn_cli(dir, "motion export typo.csv --out typo.bvh");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("'qd_r_knee_pitchh': unknown column"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "middle.bvh") || std::filesystem::exists(dir / "typo.bvh"));
  // the orientation alone: the position at home
  write_text(dir / "turned.csv", rows(",base_qw,base_qx,base_qy,base_qz", std::vector<std::string>(4, ",1,0,0,0")));
  r = humandyn_cli(dir, "motion export turned.csv --out turned.bvh");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // a base position too large to place the body (finite in the file): the row's line and the landmark
  write_text(dir / "far.csv", rows(",base_x,base_y,base_z", {",0,0,0", ",0,0,0", ",1e308,0,0", ",0,0,0"}));
  r = humandyn_cli(dir, "motion export far.csv --out far.bvh");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("far.csv: line 4: the body this row places has landmark '"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "far.bvh"));
}

TEST(MotionCli, CmuExportRoundTrip) {
  const std::filesystem::path clip = std::filesystem::path(HUMANDYN_SHARED_DATA) / "mocap" / "07_08.bvh";
  if (!std::filesystem::exists(clip)) GTEST_SKIP() << clip << " is absent (HUMANDYN_SHARED_DATA): not tested";
  const Scratch dir;
  for (const std::string& command :
       {"motion import '" + clip.string() + "' --cmu --cutoff 0 --out walk.csv --model-out body.json",
        std::string("motion export walk.csv --model body.json --out back.bvh"),
        std::string("motion import back.bvh --cutoff 0 --model body.json --out back.csv --model-out back.json"),
        std::string("motion import back.bvh --cutoff 0 --out rescaled.csv"),
        "motion import '" + clip.string() + "' --cmu --cutoff 0 --model default --out default.csv"}) {
    const CliRun r = humandyn_cli(dir, command);
    ASSERT_EQ(r.exit_code, 0) << command << "\n" << r.err;
    if (command.find("--model body.json --out back.csv") != std::string::npos) {  // the clip's own body: no warning
      EXPECT_EQ(r.err.find("warning"), std::string::npos) << command << "\n" << r.err;
    }
    if (command.find("--model default") != std::string::npos) {  // the built-in body: its forearm 42 % too long
      EXPECT_NE(r.err.find("warning: " + clip.string() + ": the body's a9 is 0.2689 m, the clip's elbow-wrist"),
                std::string::npos)
          << r.err;
      std::size_t warnings = 0;
      for (std::size_t at = r.err.find("warning: "); at != std::string::npos; at = r.err.find("warning: ", at + 1))
        ++warnings;
      EXPECT_EQ(warnings, 5u) << r.err;  // a1, a2, d4, d6 and a9 (docs/motion.md)
    }
  }
  const double worst = worst_angle_difference(dir / "walk.csv", dir / "back.csv");
  EXPECT_LT(worst, 1e-6) << "rad";
  RecordProperty("worst_angle_rad", fmt_g(worst));
  const cli::CsvTable walk = cli::read_csv((dir / "walk.csv").string(), keep_text),
                      back = cli::read_csv((dir / "back.csv").string(), keep_text);
  int same_phase = 0;
  for (std::size_t k = 0; k < walk.rows.size(); ++k)
    same_phase += walk.text(k, walk.column("phase")) == back.text(k, back.column("phase"));
  RecordProperty("same_phase", std::to_string(same_phase) + "/" + std::to_string(walk.rows.size()));
  EXPECT_EQ(read_text(dir / "back.json"), read_text(dir / "body.json"));
  // what the docs say of the other ways: the exported clip imported without --model (a body scaled anew,
  // the toe's drop re-measured from the exported feet), and the clip fitted with the built-in body (its
  // 0.19 m foot): the ankle angles move (by a constant; the other joints stay)
  const double rescaled = worst_angle_difference(dir / "walk.csv", dir / "rescaled.csv"),
               built_in = worst_angle_difference(dir / "walk.csv", dir / "default.csv");
  EXPECT_GT(rescaled, 1e-3) << "rad";
  EXPECT_GT(built_in, 1e-3) << "rad";
  RecordProperty("ankle_rescaled_rad", fmt_g(rescaled));
  RecordProperty("ankle_default_body_rad", fmt_g(built_in));
}

TEST(MotionCli, AnImportThatCannotWriteOneOutputWritesNeither) {
  // the states and the model file are committed together: a device that refuses its output (/dev/full)
  // leaves the other file unwritten, and an earlier one as it was
  const Scratch dir;
  write_text(dir / "clip.bvh", landmarks_bvh(short_walk(1.0 / 60)));
  write_text(dir / "body.json", "earlier\n");
  const CliRun model_fails = humandyn_cli(dir, "motion import clip.bvh --up z --out states.csv --model-out /dev/full");
  EXPECT_EQ(model_fails.exit_code, 1);
  EXPECT_NE(model_fails.err.find("/dev/full: writing failed"), std::string::npos) << model_fails.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "states.csv"));
  const CliRun states_fail = humandyn_cli(dir, "motion import clip.bvh --up z --out /dev/full --model-out body.json");
  EXPECT_EQ(states_fail.exit_code, 1);
  EXPECT_EQ(read_text(dir / "body.json"), "earlier\n");
  // and both when both can be written
  ASSERT_EQ(humandyn_cli(dir, "motion import clip.bvh --up z --out states.csv --model-out body.json").exit_code, 0);
  EXPECT_EQ(read_text(dir / "states.csv").rfind("t,phase,stance,", 0), 0u);
  EXPECT_NE(read_text(dir / "body.json").find("\"landmarks\""), std::string::npos);
}

// On a terminal a folder import's progress is one line, rewritten after each clip: a clip's warning clears
// it and stands on a line of its own (it once followed "1/3 clips" on that line). script(1) (util-linux,
// in every Debian system) gives the command a terminal.
TEST(MotionCli, AFolderImportsWarningsStandOnLinesOfTheirOwnOnATerminal) {
  const Scratch dir;
  const auto in_dir = [&](const std::string& command) {
    return std::system(("cd '" + dir.dir().string() + "' && " + command).c_str());
  };
  if (in_dir("script -qec true /dev/null > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "script(1) cannot open a pseudo-terminal here";
  const LandmarkClip clip = short_walk(1.0 / 120);
  std::filesystem::create_directories(dir / "clips");
  for (const char* name : {"a.bvh", "b.bvh", "c.bvh"}) write_text(dir / "clips" / name, landmarks_bvh(clip));
  // read with the wrong up axis: every clip warns
  const int status = in_dir("script -qec \"'" HUMANDYN_CLI
                            "' motion import clips --up y --threads 2 --out states\" /dev/null > tty.txt 2>&1");
  const std::string tty = read_text(dir / "tty.txt");
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << tty;
  std::size_t warnings = 0;
  const std::string warning = "humandyn motion import: warning: clips/";
  for (std::size_t at = tty.find(warning); at != std::string::npos; at = tty.find(warning, at + 1)) {
    ++warnings;
    // at the line's start, after the progress line was cleared (carriage return, erase line)
    EXPECT_TRUE(at >= 4 && tty.compare(at - 4, 4, "\r\x1b[K") == 0) << tty.substr(at < 40 ? 0 : at - 40, 80);
  }
  EXPECT_GE(warnings, 3U) << tty;
  EXPECT_NE(tty.find("\rhumandyn motion import: 3/3 clips\r\n"), std::string::npos) << tty;
  EXPECT_NE(tty.find("humandyn motion import: 3 of 3 clips imported into states\r\n"), std::string::npos) << tty;
}

TEST(MotionCli, AFolderOfClipsGoesOnPastABadOne) {
  // two good clips and a malformed one: both good ones imported, the bad one reported with its line and
  // column, the exit code 1; a malformed single clip is an error naming the file, line and column
  const Scratch dir;
  const LandmarkClip clip = short_walk(1.0 / 120);
  std::filesystem::create_directories(dir / "clips");
  write_text(dir / "clips/a.bvh", landmarks_bvh(clip));
  write_text(dir / "clips/c.bvh", landmarks_bvh(clip));
  write_text(dir / "clips/e.BVH", landmarks_bvh(clip));  // the extension in any case
  write_text(dir / "clips/b.bvh", "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 zero\n}\n");
  LandmarkClip fast = clip;  // a frame time of 1e-12 s, which once crashed the contact phases
  fast.frame_time = 1e-12;
  write_text(dir / "clips/d.bvh", landmarks_bvh(fast));
  write_text(dir / "clips/notes.txt", "not a clip");
  CliRun r = humandyn_cli(dir, "motion import clips --up z --threads 2 --out states");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("4/5 clips") == std::string::npos ? r.err.find("5/5 clips") : 0, std::string::npos) << r.err;
  EXPECT_NE(r.err.find("3 of 5 clips imported into states; 2 failed:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("\n  clips/b.bvh:4:"), std::string::npos) << r.err;  // the clip named once
  EXPECT_NE(r.err.find("\n  clips/d.bvh: low-pass: cut-off 6 Hz is below a millionth"), std::string::npos) << r.err;
  for (const char* f : {"states/a.csv", "states/a.json", "states/c.csv", "states/c.json", "states/e.csv"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  EXPECT_FALSE(std::filesystem::exists(dir / "states/b.csv"));
  EXPECT_EQ(read_text(dir / "states/a.csv"), read_text(dir / "states/c.csv"));
  EXPECT_EQ(read_text(dir / "states/a.csv"), read_text(dir / "states/e.csv"));
  // a.bvh and a.BVH would write one a.csv: refused, naming both, before any clip is read
  std::filesystem::create_directories(dir / "twins");
  write_text(dir / "twins/a.bvh", landmarks_bvh(clip));
  write_text(dir / "twins/a.BVH", landmarks_bvh(clip));
  r = humandyn_cli(dir, "motion import twins --up z --out twins_out");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("the clips twins/a.BVH and twins/a.bvh would both be written to a.csv: rename one"),
            std::string::npos)
      << r.err;
  // no clip imported: the output folders the run made are removed again. What is named CLIP.bvh but is no
  // file (a link to nothing, a folder) is a failure, said as such (it was passed over in silence); an --out
  // that is a file is refused before any clip is read
  std::filesystem::create_directories(dir / "bad/d.bvh");
  write_text(dir / "bad/b.bvh", "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 zero\n}\n");
  std::filesystem::create_symlink("missing.bvh", dir / "bad/c.bvh");
  r = humandyn_cli(dir, "motion import bad --up z --out made/deeper");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("0 of 3 clips imported into made/deeper; 3 failed:\n  bad/b.bvh:4:"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("\n  bad/c.bvh: is a symbolic link to nothing\n  bad/d.bvh: is a folder, not a clip\n"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "made"));
  r = humandyn_cli(dir, "motion import clips --up z --out clips/a.bvh");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--out clips/a.bvh is not a folder that can be made: "), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("clips imported"), std::string::npos) << r.err;
  // --cmu sets the unit, the up axis and the first frame's drop: given beside any, refused (it overrode them
  // once)
  for (const char* other : {"--unit 0.1", "--up z", "--drop-first-frame"}) {
    r = humandyn_cli(dir, std::string("motion import clips/a.bvh --cmu ") + other + " --out cmu.csv");
    EXPECT_EQ(r.exit_code, 2) << other;
    EXPECT_NE(r.err.find("--cmu"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(std::string(other).substr(0, 4)), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "cmu.csv"));
  }

  // a landmark map that cannot be read: said once, before any clip, and no output folder made
  r = humandyn_cli(dir, "motion import clips --up z --map nosuch.map --out mapped");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "humandyn motion import: nosuch.map: cannot open: No such file or directory\n");
  EXPECT_FALSE(std::filesystem::exists(dir / "mapped"));

  r = humandyn_cli(dir, "motion import clips/b.bvh --out b.csv");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("b.bvh:4:"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "b.csv"));
  // a clip's outputs beside an input of the command (its model, written into the same folder): refused
  // before any clip is imported, the input kept
  write_text(dir / "states/c.json", read_text(dir / "states/a.json"));
  const std::string model = read_text(dir / "states/c.json");
  r = humandyn_cli(dir, "motion import clips --up z --model states/c.json --out states");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("states/c.json is given to --model: an output may not replace another argument's file"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(read_text(dir / "states/c.json"), model);
}

// The lines of a text file, without their ends.
std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::size_t a = 0;
  for (std::size_t b; (b = text.find('\n', a)) != std::string::npos; a = b + 1) out.push_back(text.substr(a, b - a));
  return out;
}

// The cells of a CSV line without quotes.
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out(1);
  for (const char c : line)
    if (c == ',')
      out.emplace_back();
    else
      out.back().push_back(c);
  return out;
}

std::string joined(const std::vector<std::string>& v, const std::vector<bool>& keep) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (keep[i]) s += (s.empty() ? "" : ",") + v[i];
  return s;
}

TEST(MotionCli, CmuWalkFlagsFireOnAFixedBaseNotOnTheMovingFoot) {
  // 07_08, a real walk: the middle third of each single-support phase inside the clip (the foot flat on the
  // ground), run through `id --ground-reaction` with the stance foot's motion and without it (the foot nailed
  // to its home pose): the centre of pressure leaves the sole, or the foot pulls, on nearly every fixed-base
  // row and on few moving-base rows
  const std::filesystem::path clip = std::filesystem::path(HUMANDYN_SHARED_DATA) / "mocap" / "07_08.bvh";
  if (!std::filesystem::exists(clip)) GTEST_SKIP() << clip << " is absent (HUMANDYN_SHARED_DATA): not tested";
  const Scratch dir;
  CliRun r = humandyn_cli(dir, "motion import '" + clip.string() + "' --cmu --out walk.csv --model-out body.json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("beyond +-180"), std::string::npos) << r.err;  // (AFitATurnAwayAfterABadFrameIsNamed)
  const std::vector<std::string> rows = lines(read_text(dir / "walk.csv"));
  const std::vector<std::string> header = cells(rows[0]);
  const auto at = [&](const std::string& name) {
    return std::size_t(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::size_t phase = at("phase");
  ASSERT_LT(phase, header.size());
  std::vector<bool> all(header.size(), true), fixed(header.size(), true);
  for (std::size_t c = 0; c < header.size(); ++c) fixed[c] = header[c].rfind("base_", 0) != 0;
  std::string moving_text = rows[0] + "\n", fixed_text = joined(header, fixed) + "\n";
  int stretches = 0, n = 0;
  for (std::size_t a = 1; a < rows.size();) {
    std::size_t b = a;
    const std::string p = cells(rows[a])[phase];
    while (b < rows.size() && cells(rows[b])[phase] == p) ++b;
    if ((p == "right" || p == "left") && a > 1 && b < rows.size() && b - a >= 40) {
      ++stretches;
      for (std::size_t k = a + (b - a) / 3; k < b - (b - a) / 3; ++k, ++n) {
        moving_text += rows[k] + "\n";
        fixed_text += joined(cells(rows[k]), fixed) + "\n";
      }
    }
    a = b;
  }
  ASSERT_GE(stretches, 3) << "single-support phases of 40 frames or more inside the clip";
  write_text(dir / "moving.csv", moving_text);
  write_text(dir / "fixed.csv", fixed_text);
  const auto flagged = [&](const std::string& in) {
    const CliRun id = humandyn_cli(dir, "id --model body.json --ground-reaction --in " + in + " --out tau.csv");
    EXPECT_EQ(id.exit_code, 0) << id.err;
    const cli::CsvTable t = cli::read_csv((dir / "tau.csv").string(), keep_text);
    const std::vector<double> pulls = column(t, "foot_pulls"), outside = column(t, "cop_outside_sole");
    int count = 0;
    for (std::size_t k = 0; k < pulls.size(); ++k) count += pulls[k] != 0 || outside[k] != 0;
    return count;
  };
  const int on_fixed = flagged("fixed.csv"), on_moving = flagged("moving.csv");
  RecordProperty("flagged",
                 std::to_string(on_fixed) + " fixed, " + std::to_string(on_moving) + " moving of " + std::to_string(n));
  EXPECT_GE(on_fixed, 0.95 * n) << on_fixed << " of " << n << " fixed-base rows flagged";
  EXPECT_LE(on_moving, 0.3 * n) << on_moving << " of " << n << " moving-base rows flagged";
}

TEST(MotionCli, AFitATurnAwayAfterABadFrameIsNamed) {
  // 07_08 with the root turned 180 degrees about its first channel's axis in one frame (the file's frame 51):
  // the fit follows the angles through it continuously and goes on a turn away from them, so the hips'
  // anatomical flexion reads about 400 degrees afterwards. The import warns, naming the first joint and
  // frame beyond +-180 degrees.
  const std::filesystem::path clip = std::filesystem::path(HUMANDYN_SHARED_DATA) / "mocap" / "07_08.bvh";
  if (!std::filesystem::exists(clip)) GTEST_SKIP() << clip << " is absent (HUMANDYN_SHARED_DATA): not tested";
  const Scratch dir;
  std::vector<std::string> text = lines(read_text(clip));
  const std::size_t frames =
      std::size_t(
          std::find_if(text.begin(), text.end(), [](const std::string& l) { return l.rfind("Frame Time", 0) == 0; }) -
          text.begin()) +
      1;
  std::vector<std::string> values;  // the frame's numbers, split at blanks
  for (std::size_t at = 0, end; at < text.at(frames + 50).size(); at = end + 1) {
    end = std::min(text[frames + 50].find_first_of(" \t\r", at), text[frames + 50].size());
    if (end > at) values.push_back(text[frames + 50].substr(at, end - at));
  }
  values.at(3) = std::to_string(std::stod(values.at(3)) + 180);  // the root's Zrotation (degrees)
  std::string joined_text, row;
  for (const std::string& v : values) row += (row.empty() ? "" : " ") + v;
  text[frames + 50] = row;
  for (const std::string& l : text) joined_text += l + "\n";
  write_text(dir / "bad.bvh", joined_text);
  const CliRun bad = humandyn_cli(dir, "motion import bad.bvh --cmu --out bad.csv");
  ASSERT_EQ(bad.exit_code, 0) << bad.err;
  // the first joint and frame beyond: the left hip, at the bad frame itself (the filter spreads the turn)
  EXPECT_NE(bad.err.find("humandyn motion import: warning: bad.bvh: l_hip_flexion is "), std::string::npos) << bad.err;
  EXPECT_NE(
      bad.err.find(" degrees at the file's frame 51 (0.417 s into the file), beyond +-180: the fit has gone a "
                   "whole turn (360 degrees) from the angles before it, as it does after a bad frame (say, the "
                   "root turned half a turn for one frame): check the clip around that frame (the filter spreads a bad "
                   "frame over the frames around it)\n"),
      std::string::npos)
      << bad.err;
  // (CmuWalkFlagsFireOnAFixedBaseNotOnTheMovingFoot: the sound clip draws no such warning)
}

// A clip that needs more memory than the process may have (its address space held to 100 MB with ulimit):
// the import says so, alone or in a folder, and writes nothing (it said "std::bad_alloc").
TEST(MotionCli, AClipTooLargeForTheMemorySaysSo) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit this test sets";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit this test sets";
#endif
#endif
  const Scratch dir;
  std::string text =
      "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zposition\n}\n"
      "MOTION\nFrames: 4000000\nFrame Time: 0.01\n";
  for (int k = 0; k < 4000000; ++k) text += "1 2 3\n";
  std::filesystem::create_directories(dir / "clips");
  write_text(dir / "clips" / "big.bvh", text);
  const auto run = [&](const std::string& arguments) {
    const int status =
        std::system(("cd '" + dir.dir().string() + "' && ulimit -v 100000 && '" HUMANDYN_CLI "' motion import " +
                     arguments + " 2> err.txt")
                        .c_str());
    return std::pair{WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(dir / "err.txt")};
  };
  const auto [code, err] = run("clips/big.bvh --out big.csv");
  EXPECT_EQ(code, 1) << err;
  EXPECT_EQ(err, "humandyn motion import: out of memory: the input needs more memory than the process can have\n");
  EXPECT_FALSE(std::filesystem::exists(dir / "big.csv"));
  const auto [folder_code, folder_err] = run("clips --out states");
  EXPECT_EQ(folder_code, 1) << folder_err;
  EXPECT_NE(folder_err.find("big.bvh: out of memory: the clip needs more memory than the process can have"),
            std::string::npos)
      << folder_err;
  EXPECT_FALSE(std::filesystem::exists(dir / "states" / "big.csv"));
}

}  // namespace

}  // namespace test_motion_cli
