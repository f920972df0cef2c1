// humandyn motion import: motion-capture clips (BVH) in, the stance-rooted states `id` reads out
// (docs/motion.md). One clip, or every .bvh of a folder across all cores.
#include "cli/atomic_file.hpp"
#include "cli/base_columns.hpp"
#include "cli/commands.hpp"
#include "cli/csv.hpp"
#include "cli/model_json.hpp"
#include "cli/states_command.hpp"
#include "humandyn/anatomy.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/bvh.hpp"
#include "humandyn/motion/import.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace humandyn::cli {

namespace {

namespace fs = std::filesystem;
namespace hm = humandyn::motion;

struct ImportCommandOptions {
  std::string clip, out, map, model_out;
  double mass = 70, cutoff = 6, unit = 1;
  hm::UpAxis up = hm::UpAxis::y;
  bool drop_first_frame = false, cmu = false;
  long threads = 0;  // 0: every core
};

// The header of a states file: t, phase, stance, the stance foot's motion, the right-stance model's q, qd,
// qdd, and the anatomical angles.
std::vector<std::string> states_header(const std::vector<std::string>& joints) {
  std::vector<std::string> h{"t", "phase", "stance"};
  for (const BaseGroup g : {BaseGroup::Position, BaseGroup::Orientation, BaseGroup::AngularVelocity,
                            BaseGroup::AngularAcceleration, BaseGroup::Acceleration})
    for (auto& c : base_columns(g)) h.push_back(c);
  for (const char* prefix : {"q_", "qd_", "qdd_"})
    for (auto& c : joint_columns(joints, prefix)) h.push_back(c);
  for (const auto& a : anatomical_joints) h.emplace_back(a.name);
  return h;
}

// One clip through the pipeline: the states file (and the scaled body's model file) written all or nothing.
void import_one(const std::string& clip_path, const std::string& out, const std::string& model_out,
                const ImportCommandOptions& o) {
  hm::LandmarkOptions lo;
  lo.world = {o.unit, o.up};
  lo.drop_first_frame = o.drop_first_frame;
  if (!o.map.empty()) lo.map = hm::read_landmark_map(o.map);
  const hm::LandmarkClip marks = hm::to_landmarks(hm::read_bvh_file(clip_path), lo);
  hm::ImportOptions io;
  io.scale.mass = o.mass;
  io.filter.cutoff = o.cutoff;
  const hm::ImportedClip m = hm::import_clip(marks, io);

  const ModelDescription<double> body = human_description(m.body.parameters);
  const hm::StanceForms forms(m.body.parameters);
  CsvWriter csv(out, states_header(joint_names(body)));
  std::vector<std::string> cells;
  hm::StanceFrame right;
  std::array<double, 16> anatomical{};
  for (std::size_t k = 0; k < m.stance.size(); ++k) {
    // q, qd, qdd of the right-stance model on every row (id maps a left row to the left foot's model);
    // the base motion is the row's stance foot's
    forms.stance_state(hm::Foot::right, m.motion.frames[k], right);
    const hm::StanceFrame& s = m.stance[k];
    const Eigen::Quaterniond r(s.base.pose.R);
    cells = {format_number(double(k) * marks.frame_time), hm::phase_name(m.phases.phase[k]),
             s.foot == hm::Foot::right ? "right" : "left"};
    const auto put = [&](const auto& v) {
      for (Eigen::Index i = 0; i < v.size(); ++i) cells.push_back(format_number(v[i]));
    };
    put(s.base.pose.p);
    put(Eigen::Vector4d(r.w(), r.x(), r.y(), r.z()));
    put(s.base.w);
    put(s.base.wd);
    put(s.base.a);
    put(right.q);
    put(right.qd);
    put(right.qdd);
    anatomical_angles(BodyForm::RightStance, right.q, anatomical);
    for (const double a : anatomical) cells.push_back(format_number(a));
    csv.row_cells(cells);
  }
  if (!model_out.empty()) write_file_atomically(model_out, write_model_json(body));
  csv.commit();
}

// Every .bvh of a folder, on `threads` threads; a progress line on stderr, a summary of the failures.
int import_folder(const ImportCommandOptions& o) {
  std::vector<fs::path> clips;
  for (const auto& e : fs::directory_iterator(o.clip))
    if (e.is_regular_file() && e.path().extension() == ".bvh") clips.push_back(e.path());
  std::sort(clips.begin(), clips.end());
  if (clips.empty()) throw UsageError("no .bvh file in the folder " + o.clip);
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (!fs::is_directory(o.out)) throw UsageError("--out " + o.out + " is not a folder that can be made");

  std::atomic<std::size_t> next{0}, done{0};
  std::mutex report;
  std::vector<std::string> failures(clips.size());
  const auto work = [&] {
    for (std::size_t i; (i = next++) < clips.size();) {
      const std::string stem = clips[i].stem().string();
      try {
        import_one(clips[i].string(), (fs::path(o.out) / (stem + ".csv")).string(),
                   (fs::path(o.out) / (stem + ".json")).string(), o);
      } catch (const std::exception& e) {
        failures[i] = e.what();
      }
      const std::lock_guard lock(report);
      fmt::print(stderr, "\rhumandyn motion import: {}/{} clips", ++done, clips.size());
    }
  };
  const std::size_t n =
      std::min(clips.size(), std::size_t(o.threads > 0 ? o.threads : std::max(1u, std::thread::hardware_concurrency())));
  std::vector<std::thread> pool;
  for (std::size_t t = 0; t < n; ++t) pool.emplace_back(work);
  for (auto& t : pool) t.join();
  fmt::print(stderr, "\n");

  const auto failed = std::count_if(failures.begin(), failures.end(), [](const auto& f) { return !f.empty(); });
  fmt::print(stderr, "humandyn motion import: {} of {} clips imported into {}", clips.size() - std::size_t(failed),
             clips.size(), o.out);
  if (failed == 0)
    fmt::print(stderr, "\n");
  else
    fmt::print(stderr, "; {} failed:\n", failed);
  for (std::size_t i = 0; i < clips.size(); ++i)
    if (!failures[i].empty()) fmt::print(stderr, "  {}: {}\n", clips[i].string(), failures[i]);
  return failed == 0 ? 0 : 1;
}

int run_import(ImportCommandOptions o) {
  if (o.cmu) {
    o.unit = hm::cmu_metres_per_unit;
    o.up = hm::UpAxis::y;
    o.drop_first_frame = true;
  }
  if (!(o.mass > 0)) throw UsageError("--mass must be positive, got " + format_number(o.mass));
  if (o.cutoff < 0) throw UsageError("--cutoff must be 0 (no filter) or positive, got " + format_number(o.cutoff));
  if (!(o.unit > 0)) throw UsageError("--unit must be positive, got " + format_number(o.unit));
  if (fs::is_directory(o.clip)) {
    if (!o.model_out.empty()) throw UsageError("--model-out goes with one clip; a folder gets CLIP.json per clip");
    return import_folder(o);
  }
  try {
    import_one(o.clip, o.out, o.model_out, o);
  } catch (const hm::BvhError& e) {
    throw InputError(e.what());
  } catch (const hm::MotionError& e) {
    throw InputError(e.what());
  }
  return 0;
}

}  // namespace

Command add_motion(CLI::App& humandyn) {
  CLI::App* motion = humandyn.add_subcommand("motion", "motion capture in: BVH clips to the states `id` reads");
  motion->require_subcommand(1);
  const auto o = std::make_shared<ImportCommandOptions>();
  CLI::App* c = motion->add_subcommand(
      "import",
      "a BVH clip (or every .bvh of a folder) fitted, filtered and split by stance foot\n\n"
      "Reads the clip's joint centres, scales the body to them (de Leva's segments, --mass), fits its joint\n"
      "angles and pelvis per frame, filters (zero-lag Butterworth, --cutoff) and differentiates, finds the\n"
      "feet's contact phases and writes, per frame, the states of the body rooted at the stance foot with\n"
      "that foot's motion as its base: the input of `humandyn id --model BODY.json` (docs/motion.md).");
  c->add_option("CLIP", o->clip, "a BVH file, or a folder: every .bvh in it, across all cores")->required();
  c->add_option("--out", o->out,
                "the states (CSV): t, phase (right, left, double, flight), stance (right,\n"
                "left), base_x.. base_qw.. base_wx.. base_wdx.. base_ax.. (the stance foot's\n"
                "ankle frame, world), q_, qd_, qdd_ of the right-stance model's joints, and the\n"
                "anatomical angles (rad; r_knee_flexion, ...). For a folder: a folder,\n"
                "CLIP.csv and CLIP.json (the scaled body) per clip")
      ->required();
  c->add_option("--model-out", o->model_out, "the body scaled to the clip, as `humandyn model --json` writes it");
  add_number(*c, "--mass", o->mass, "the body's mass, kg (default 70)");
  add_number(*c, "--cutoff", o->cutoff, "the low-pass cut-off, Hz (default 6; 0: no filter)");
  c->add_option("--map", o->map, "a landmark map file: BVH joints for the body's landmarks (docs/motion.md)");
  add_number(*c, "--unit", o->unit, "metres per file unit (default 1)");
  add_choice(*c, "--up", o->up, {{"y", hm::UpAxis::y}, {"z", hm::UpAxis::z}}, "the file's up axis (default y)");
  c->add_flag("--drop-first-frame", o->drop_first_frame, "leave out the clip's first frame (an added T-pose)");
  c->add_flag("--cmu", o->cmu,
              "CMU's clips in Hahne's conversion: --unit 0.056444 --up y --drop-first-frame");
  add_whole_number(*c, "--threads", o->threads, "threads for a folder (default: every core)");
  c->callback([] {});
  return {motion, [o, c] { return c->parsed() ? run_import(*o) : 0; }};
}

}  // namespace humandyn::cli
