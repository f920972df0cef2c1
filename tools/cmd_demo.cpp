// humandyn demo: the seed paper's scenarios (standing upright; the left arm raised forward by 90
// degrees) on the paper's model and on the default model, printed beside the paper's Table 2 and drawn
// as SVG (front and side view, every joint's torque labelled).
#include "cli/atomic_file.hpp"
#include "cli/body_svg.hpp"
#include "cli/commands.hpp"
#include "cli/csv.hpp"
#include "cli/model_source.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/data.hpp"
#include "text/shown.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace humandyn::cli {

namespace {

constexpr double pi = 3.14159265358979323846;

struct DemoOptions {
  ModelOptions model;
  bool model_given = false;
  std::string out = "humandyn-demo";
};

// What the paper prints, by its joint number (1-based): Table 2 for the raised arm, and the two torques
// its text gives for standing.
constexpr std::array<double, 9> paper_table2{-9.9, -9.9, 98.5, 9.9, -9.6, 0, -9.6, 0, -1.8};
struct PaperValue {
  int joint;
  double value;
  const char* text;
};
constexpr std::array<PaperValue, 2> paper_standing{{{3, 98.55, "98.55"}, {14, 0, "0"}}};

struct Scenario {
  std::string key, title;
  std::vector<std::pair<std::string, double>> angles;  // joints away from 0 (by name), rad
};

const std::vector<Scenario>& scenarios() {
  static const std::vector<Scenario> list{
      {"arm_forward",
       "the left arm raised forward by 90 degrees (l_shoulder_pitch = -pi/2, every other joint 0)",
       {{"l_shoulder_pitch", -pi / 2}}},
      {"standing", "standing upright (every joint 0)", {}},
  };
  return list;
}

struct Subject {
  std::string key;    // names the output files
  std::string label;  // the key as tables, messages and drawings show it (text::shown: a file's stem may hold
                      // any byte, which neither a terminal nor an SVG document should get raw)
  AnyModel<double> model;
};

// The paper's joint k (1-based) in a model with the seed body's names.
int seed_joint(const AnyModel<double>& model, int k) { return model.joint_index(seed_joint_names[std::size_t(k - 1)]); }

std::string torque_cell(double tau) {
  // exact zeros print as 0; anything else, however small, keeps its sign and three decimals
  if (tau == 0) return "0";
  return fmt::format("{:.3f}", tau);
}

// The static torque of joint i computed without Newton-Euler: minus the moment, about the joint's
// axis, of the weights of every link beyond the joint (forward kinematics only).
double weight_moment_torque(const AnyModel<double>& model, const Data<AnyModel<double>>& data, int i) {
  const auto& j = model.joint(i);
  Pose<double> axis_frame = j.parent < 0 ? model.base_pose() : data.oMi[std::size_t(j.parent)];
  if (j.mounted) axis_frame = axis_frame * Pose<double>{j.mount_R, j.mount_p};
  const Eigen::Vector3d axis = axis_frame.R.col(2);
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (int k = i; k < model.size(); ++k) {
    int a = k;
    while (a > i) a = model.joint(a).parent;  // parents come first: k is beyond i iff the walk meets i
    if (a != i) continue;
    moment += (data.com_world[std::size_t(k)] - axis_frame.p).cross(model.joint(k).mass * model.gravity());
  }
  return -axis.dot(moment);
}

// Joint i's axis in the world at the pose of `data`, as "+x", "-y", ... when it lies along a world axis.
std::string axis_text(const AnyModel<double>& model, const Data<AnyModel<double>>& data, int i) {
  const auto& j = model.joint(i);
  Pose<double> axis_frame = j.parent < 0 ? model.base_pose() : data.oMi[std::size_t(j.parent)];
  if (j.mounted) axis_frame = axis_frame * Pose<double>{j.mount_R, j.mount_p};
  const Eigen::Vector3d z = axis_frame.R.col(2);
  for (int k = 0; k < 3; ++k)
    if (std::abs(std::abs(z[k]) - 1) < 1e-12) return std::string(z[k] > 0 ? "+" : "-") + "xyz"[k];
  return fmt::format("({:.2f},{:.2f},{:.2f})", z.x(), z.y(), z.z());
}

// Table 1's symbols read back from a seed model, so that the parameters printed are the ones used.
void print_parameters(const std::vector<Subject>& subjects) {
  fmt::print("Parameters (Table 1's symbols, read from each model): lengths in m, masses in kg\n");
  fmt::print(
      "  {:<9} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>8} {:>7}\n",
      "model", "a1", "a2", "d4", "d6", "d7", "a8", "a9", "a16", "m1", "m2", "m4", "m6", "m8", "m9", "m16", "m_stance",
      "total");
  for (const auto& s : subjects) {
    const auto& J = s.model.description().joints;
    const auto at = [&](int k) -> const JointDescription<double>& { return J[std::size_t(seed_joint(s.model, k))]; };
    fmt::print(
        "  {:<9} {:7.4f} {:7.4f} {:7.4f} {:7.4f} {:7.4f} {:7.4f} {:7.4f} {:7.4f} {:7.3f} {:7.3f} {:7.3f} {:7.3f} "
        "{:7.3f} {:7.3f} {:7.3f} {:8.3f} {:7.3f}\n",
        s.label, at(1).dh.a, at(2).dh.a, at(4).dh.d, at(6).dh.d, at(7).dh.d, at(8).dh.a, at(9).dh.a, at(16).dh.a,
        at(1).body.mass, at(2).body.mass, at(4).body.mass, at(6).body.mass, at(8).body.mass, at(9).body.mass,
        at(16).body.mass, s.model.description().base_body.mass, s.model.total_mass());
  }
  fmt::print(
      "  (m1 shank, m2 thigh, m4 pelvis (massless in Table 1), m6 the trunk above it with the head, m8 upper arm,\n"
      "  m9 forearm and hand, m16 free foot; the stance foot is the base; d4 half the hip width, d7 half the\n"
      "  shoulder width, a16 the ankle height)\n");
  for (const auto& s : subjects) fmt::print("  {}: {}\n", s.label, text::shown(s.model.description().name));
  fmt::print("\n");
}

int run_demo(const DemoOptions& o) {
  if (o.out == "-") throw UsageError("--out -: the drawings and tables go to a folder, not to standard output");
  if (const std::string fault = output_folder_fault(o.out); !fault.empty())
    throw UsageError("--out " + text::shown(o.out) + " is not a folder that can be made: " + fault);
  const std::filesystem::path out_dir = o.out;
  std::vector<Subject> subjects;
  if (o.model_given) {
    const std::string& chosen = o.model.model;
    // a built-in model's name, or a file's stem (its folder and ending left out: the files go to --out)
    const bool file = has_ending(chosen, ".json") || has_ending(chosen, ".urdf");
    const std::string key = file ? std::filesystem::path(chosen).stem().string() : chosen;
    subjects.push_back({key, text::shown(key), AnyModel<double>(load_model(o.model))});
  } else {
    subjects.push_back({"paper", "paper", AnyModel<double>(human_description(paper_parameters()))});
    subjects.push_back({"default", "default", AnyModel<double>(human_description(default_parameters()))});
  }
  for (const auto& s : subjects)
    for (const char* name : seed_joint_names)
      if (s.model.joint_index(name) < 0)
        throw UsageError("model '" + s.label + "' has no joint '" + name +
                         "': the demo needs the seed body's 16 joint names");

  // every file checked before the folder is made and any is written
  std::vector<std::string> outputs;
  for (const auto& scenario : scenarios())
    for (const auto& s : subjects)
      for (const char* ending : {".svg", ".csv"})
        outputs.push_back((out_dir / (s.key + "_" + scenario.key + ending)).string());
  refuse_outputs(outputs);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw InputError(text::shown(out_dir.string()) + ": cannot create the folder: " + ec.message());

  fmt::print(
      "humandyn demo: the seed paper's scenarios, static (velocities and accelerations 0), by Newton-Euler (rnea).\n");
  fmt::print("Torques in N m: the drive torque about each joint's DH z axis, positive counter-clockwise about it.\n\n");
  print_parameters(subjects);

  // the drawings and tables, each in its temporary file until all are written: then every one replaces
  // its file, so that a failure on the way (a file that cannot be made, standard output full) leaves none
  std::vector<std::string> files;
  std::vector<std::unique_ptr<AtomicFile>> drawings;
  std::vector<std::unique_ptr<CsvWriter>> tables;
  for (const auto& scenario : scenarios()) {
    // the pose and the torques of every model
    std::vector<Eigen::VectorXd> taus;
    std::vector<std::string> wrists, axes;  // axes: of the first model's joints, by seed number
    std::vector<std::string> hip_roll;      // what loads the stance hip roll, per model
    double check = 0;
    for (const auto& s : subjects) {
      const auto& model = s.model;
      Data<AnyModel<double>> data(model);
      Eigen::VectorXd q = Eigen::VectorXd::Zero(model.size());
      for (const auto& [name, angle] : scenario.angles) q[model.joint_index(name)] = angle;
      const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.size());
      const Eigen::VectorXd tau = rnea<Terms::Full>(model, data, q, zero, zero);
      for (int i = 0; i < model.size(); ++i)  // before any file of this model and pose is written
        if (!std::isfinite(tau[i]))
          throw InputError(fmt::format("model '{}', {}: the torque of joint '{}' overflows (its masses are too large)",
                                       s.label, scenario.key, model.joint_name(i)));
      taus.push_back(tau);

      // the same torques from forward kinematics alone: the moments of the weights beyond each joint
      forward_kinematics(model, data, q);
      for (int i = 0; i < model.size(); ++i)
        check = std::max(check, std::abs(tau[i] - weight_moment_torque(model, data, i)));
      if (axes.empty())
        for (int k = 1; k <= 16; ++k) axes.push_back(axis_text(model, data, seed_joint(model, k)));
      // the stance hip roll (joint 3) holds everything beyond it at a lateral lever from the right hip
      {
        const int hip = seed_joint(model, 3);
        const Eigen::Vector3d hip_point = data.oMi[std::size_t(model.joint(hip).parent)].p;
        double mass = 0, moment_y = 0;
        for (int k = 0; k < model.size(); ++k) {
          int a = k;
          while (a > hip) a = model.joint(a).parent;
          if (a != hip) continue;
          mass += model.joint(k).mass;
          moment_y += model.joint(k).mass * (data.com_world[std::size_t(k)].y() - hip_point.y());
        }
        hip_roll.push_back(fmt::format(
            "{}: {:.3f} kg beyond joint 3, centre of mass {:.4f} m left of the right hip: m g lever = {:.3f} N m",
            s.label, mass, moment_y / mass, -model.gravity().z() * moment_y));
      }
      const Eigen::Vector3d wrist = data.oMi[std::size_t(seed_joint(model, 9))].p;
      const Eigen::Vector3d shoulder = data.oMi[std::size_t(seed_joint(model, 7))].p;
      wrists.push_back(fmt::format("{} ({:.3f}, {:.3f}, {:.3f}), {:.3f} m ahead of the shoulder", s.label, wrist.x(),
                                   wrist.y(), wrist.z(), wrist.x() - shoulder.x()));

      // the drawing and the numbers behind it
      const std::string stem = s.key + "_" + scenario.key;
      BodyDrawing drawing;
      drawing.title = s.label + " model: " + scenario.title;
      drawing.notes = {
          model.description().name,
          "static joint torques by Newton-Euler, N\u00b7m about each joint's DH z axis (positive counter-clockwise)",
          "blue: left side, red: right side, grey: the middle; the square is the fixed stance foot"};
      drawing.q = q;
      drawing.tau = tau;
      drawings.push_back(std::make_unique<AtomicFile>((out_dir / (stem + ".svg")).string()));
      drawings.back()->write(body_svg(model, drawing));
      std::vector<std::string> names;
      for (int i = 0; i < model.size(); ++i) names.push_back(model.joint_name(i));
      auto header = joint_columns(names, "q_");
      const auto tau_names = joint_columns(names, "tau_");
      header.insert(header.end(), tau_names.begin(), tau_names.end());
      tables.push_back(std::make_unique<CsvWriter>((out_dir / (stem + ".csv")).string(), header));
      std::vector<double> row(q.data(), q.data() + q.size());
      row.insert(row.end(), tau.data(), tau.data() + tau.size());
      tables.back()->row(row);
      files.push_back((out_dir / (stem + ".svg")).string());
      files.push_back((out_dir / (stem + ".csv")).string());
    }

    // the table: every joint, the paper's value where it gives one
    fmt::print("Scenario '{}': {}\n", scenario.key, scenario.title);
    fmt::print("  left wrist: ");
    for (std::size_t k = 0; k < wrists.size(); ++k) fmt::print("{}{}", k ? "; " : "", wrists[k]);
    fmt::print("\n");
    fmt::print("  {:>3}  {:<18} {:>5} {:>10}", "#", "joint", "axis",
               scenario.key == "standing" ? "paper text" : "Table 2");
    for (const auto& s : subjects) fmt::print(" {:>10}", s.label);
    fmt::print("\n");
    for (int k = 1; k <= 16; ++k) {
      std::string paper = ".";
      if (scenario.key == "standing") {
        for (const auto& p : paper_standing)
          if (p.joint == k) paper = p.text;
      } else if (k <= int(paper_table2.size())) {
        paper = fmt::format("{:g}", paper_table2[std::size_t(k - 1)]);
      }
      fmt::print("  {:3}  {:<18} {:>5} {:>10}", k, seed_joint_names[std::size_t(k - 1)], axes[std::size_t(k - 1)],
                 paper);
      for (std::size_t m = 0; m < subjects.size(); ++m)
        fmt::print(" {:>10}", torque_cell(taus[m][seed_joint(subjects[m].model, k)]));
      fmt::print("\n");
    }
    fmt::print("  axis: the joint's z axis in the world (x forward, y left, z up) in {}'s pose\n", subjects[0].label);
    if (scenario.key == "standing") {
      fmt::print("  stance hip roll by hand:\n");
      for (const auto& line : hip_roll) fmt::print("    {}\n", line);
      fmt::print("    the paper's 98.55 N m would need (mass beyond joint 3) x lever = 98.55 / 9.81 = {:.3f} kg m\n",
                 98.55 / 9.81);
    }
    fmt::print(
        "  check: each torque equals minus the moment of the weights beyond its joint about the joint's axis\n"
        "  (from forward kinematics alone) within {:.1e} N m\n\n",
        check);
  }
  if (std::fflush(stdout) != 0) return 1;  // (main says standard output failed; nothing is written)
  std::vector<AtomicFile*> written;        // every file or none
  for (const auto& f : drawings) written.push_back(f.get());
  for (const auto& t : tables) written.push_back(&t->file());
  commit_together(written);
  fmt::print("Written:");
  for (const auto& f : files) fmt::print(" {}", text::shown(f));
  fmt::print("\n");
  return std::fflush(stdout) == 0 ? 0 : 1;
}

}  // namespace

Command add_demo(CLI::App& humandyn) {
  const auto o = std::make_shared<DemoOptions>();
  CLI::App* c = humandyn.add_subcommand(
      "demo",
      "the seed paper's scenarios beside its Table 2, with SVG drawings\n\n"
      "The seed paper's scenarios, standing upright and the left arm raised forward by 90 degrees, as static\n"
      "torques (N m) beside the paper's Table 2, on the paper's model and the default model (or on --model\n"
      "alone: any model with the seed body's joint names). Writes to DIR (default: humandyn-demo), for each\n"
      "model and scenario, <model>_<scenario>.svg (front and side view, torques labelled) and\n"
      "<model>_<scenario>.csv (the pose q_<joint> and the torques tau_<joint>, full precision).");
  add_model_options(*c, o->model)->each([o](const std::string&) { o->model_given = true; });
  c->add_option("--out", o->out, "the folder of the drawings and tables (default: humandyn-demo)")->option_text("DIR");
  return {c, [o] { return run_demo(*o); }};
}

}  // namespace humandyn::cli
