// humandyn motion import: motion-capture clips (BVH) in, the stance-rooted states `id` reads out
// (docs/motion.md). One clip, or every .bvh (or .BVH) of a folder across all cores. humandyn motion export: such
// states back out as a BVH clip of the body's landmarks.
#include "cli/atomic_file.hpp"
#include "cli/base_columns.hpp"
#include "cli/commands.hpp"
#include "cli/cores.hpp"
#include "cli/csv.hpp"
#include "cli/joint_table.hpp"
#include "cli/model_json.hpp"
#include "cli/model_source.hpp"
#include "cli/print.hpp"
#include "cli/stance_switching.hpp"
#include "cli/states_command.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/anatomy.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/bvh.hpp"
#include "humandyn/motion/import.hpp"
#include "humandyn/stance.hpp"
#include "text/shown.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>
#include <new>
#include <numbers>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <unistd.h>

namespace humandyn::cli {

namespace {

namespace fs = std::filesystem;
namespace hm = humandyn::motion;

// A body of the seed's shape given by --model, for the fit (import) or the landmarks (export).
struct GivenBody {
  ModelDescription<double> description;  // as the option names it
  hm::ClipBody body;                     // its lengths (from the DH rows) and landmark geometry
};
GivenBody given_body(const ModelOptions& options);

// A folder import's progress on standard error: on a terminal one line, rewritten after each clip, which
// a clip's warning clears first and puts back after, so that neither runs into the other; in a log a
// line a clip. Shared by the worker threads.
struct Progress {
  std::mutex lock;
  bool terminal = false;
  std::size_t done = 0, total = 0;

  void line() {
    cli::print(stderr, "{}humandyn motion import: {}/{} clips{}", terminal ? "\r" : "", done, total,
               terminal ? "" : "\n");
  }
  void clip_done() {
    const std::lock_guard hold(lock);
    ++done;
    line();
  }
  void warning(const std::string& text) {
    const std::lock_guard hold(lock);
    cli::print(stderr, "{}{}", terminal ? "\r\x1b[K" : "", text);  // (clear the line: carriage return, erase)
    if (terminal && done > 0) line();
  }
};

struct ImportCommandOptions {
  std::string clip, out, map, model_out;
  ModelOptions model;  // --model (model_given): the body to fit; else one scaled to each clip
  bool model_given = false;
  std::optional<GivenBody> given;            // that body, read once
  std::optional<hm::LandmarkMap> landmarks;  // --map's, read once
  double mass = 70, cutoff = 6, unit = 1;
  hm::UpAxis up = hm::UpAxis::y;
  bool drop_first_frame = false, cmu = false;
  long threads = 0;              // 0: every core the process may run on
  Progress* progress = nullptr;  // a folder import's, where its clips' warnings go
};

// A warning of the import, on standard error: through a folder import's progress line where there is one.
template <class... A>
void warn(const ImportCommandOptions& o, fmt::format_string<A...> format, A&&... args) {
  const std::string text = "humandyn motion import: warning: " + fmt::format(format, std::forward<A>(args)...);
  if (o.progress)
    o.progress->warning(text);
  else
    cli::print(stderr, "{}", text);
}

// The header of a states file: t, phase, stance, the stance foot's motion, the right-stance model's q, qd,
// qdd, and the anatomical angles.
std::vector<std::string> states_header(const std::vector<std::string>& joints) {
  std::vector<std::string> h{"t", "phase", "stance"};
  for (auto& c : state_columns({BaseGroup::Position, BaseGroup::Orientation, BaseGroup::AngularVelocity,
                                BaseGroup::AngularAcceleration, BaseGroup::Acceleration},
                               joints, {"q_", "qd_", "qdd_"}))
    h.push_back(std::move(c));
  for (const auto& a : anatomical_joints) h.emplace_back(a.name);
  return h;
}

// The statures a scaled body may have before import warns of the clip's unit (m).
constexpr double min_stature = 0.5, max_stature = 2.5;

// One clip through the pipeline: the states file (and the scaled body's model file) written all or nothing.
void import_one(const std::string& clip_path, const std::string& out, const std::string& model_out,
                const ImportCommandOptions& o) {
  hm::LandmarkOptions lo;
  lo.world = {o.unit, o.up};
  lo.drop_first_frame = o.drop_first_frame;
  if (o.landmarks) lo.map = *o.landmarks;
  const hm::LandmarkClip marks = hm::to_landmarks(hm::read_bvh_file(clip_path), lo);
  hm::ImportOptions io;
  io.scale.mass = o.mass;
  io.filter.cutoff = o.cutoff;
  if (o.given) io.body = o.given->body;
  const hm::ImportedClip m = hm::import_clip(marks, io);
  for (const hm::LengthMismatch& x : m.mismatched)
    warn(o,
         "{}: the body's {} is {:.4g} m, the clip's {} distance {:.4g} m "
         "({:+.1f} %): is it the clip's body?\n",
         clip_path, humandyn::detail::dimension(x.clip.dim).name, x.body, x.clip.between, x.clip.length,
         100 * (x.body - x.clip.length) / x.clip.length);
  if (o.given && !m.waist_pitch_fitted && o.given->body.lower_back_length > 0)
    warn(o,
         "{}: the clip's lower back stands within {:g} m of the mid-hip "
         "point: the body's, {:.4g} m above it, is not fitted and the waist pitch is held at 0\n",
         clip_path, io.scale.min_lower_back, o.given->body.lower_back_length);
  // feet never still in the world (a treadmill, walking in place): the contact phases, and a scaled body's
  // toe drop, are found from the feet's speed (not said where the clip's size already looks wrong: a body
  // scaled outside a person's stature, or a given body's lengths off the clip's)
  const bool person_sized = m.body.stature >= min_stature && m.body.stature <= max_stature;  // (else: the unit)
  const int still = m.body.planted_frames;
  if (still < 10 && (o.given ? m.mismatched.empty() : person_sized))
    warn(o,
         "{}: a foot is still (its ankle slower than 0.5 m/s, its toe than 0.3 m/s) {} time(s) over the frames of "
         "both feet, fewer than 10: {}the contact phases, found from the feet's speed{}, may read flight where a "
         "foot is down (a treadmill, or walking in place?){}\n",
         clip_path, still,
         o.given ? "" : "the toe is taken to lie on the sole (its drop below the ankle not measured), and ",
         o.given ? "" : " too", o.given ? "" : ". --model takes a body whose \"landmarks\" give the toe's drop");
  // a clip read in another unit, or with another up axis, still fits; what then looks wrong is said
  if (!o.given && !person_sized)
    warn(o,
         "{}: the body scaled to it stands {:.3g} m tall, outside a "
         "person's {:g} to {:g} m: is the file's unit {:g} m (--unit; --cmu for CMU's clips)?\n",
         clip_path, m.body.stature, min_stature, max_stature, o.unit);
  const auto head_up = [](const auto& f) {
    const auto z = [&f](hm::Landmark l) { return f[std::size_t(l)].z(); };
    return z(hm::Landmark::head) > std::max(z(hm::Landmark::r_ankle), z(hm::Landmark::l_ankle));
  };
  const auto upright = std::count_if(marks.frames.begin(), marks.frames.end(), head_up);
  if (2 * std::size_t(upright) < marks.frames.size())
    warn(o,
         "{}: the head is above both ankles in {} of {} frames: is the "
         "file's up axis {} (--up)?\n",
         clip_path, upright, marks.frames.size(), o.up == hm::UpAxis::y ? "y" : "z");

  // the body the states were fitted with: a given one standing as the fit took it (given_body)
  ModelDescription<double> body = o.given ? o.given->description : human_description(m.body.parameters);
  body.base_pose = m.body.parameters.base_pose;
  const hm::StanceForms forms(m.body.parameters);
  CsvWriter csv(out, states_header(joint_names(body)));
  std::vector<std::string> cells;
  hm::StanceFrame right;
  std::array<double, 16> anatomical{};
  // the first angle beyond a turn's half, which no joint of the body reaches: the fit went on a turn away
  // from the angles before it (its angles stay continuous), as after a bad frame
  std::size_t beyond_frame = 0, beyond_joint = anatomical.size();
  double beyond_angle = 0;  // rad
  for (std::size_t k = 0; k < m.stance.size(); ++k) {
    // q, qd, qdd of the right-stance model on every row (id maps a left row to the left foot's model);
    // the base motion is the row's stance foot's
    forms.stance_state(hm::Foot::right, m.motion.frames[k], right);
    const hm::StanceFrame& s = m.stance[k];
    cells = {format_number(double(k) * marks.frame_time), hm::phase_name(m.phases.phase[k]),
             s.foot == hm::Foot::right ? "right" : "left"};
    for (const double v : stance_state_values(s.base, right.q, right.qd, right.qdd)) cells.push_back(format_number(v));
    anatomical_angles(BodyForm::RightStance, right.q, anatomical);
    for (const double a : anatomical) cells.push_back(format_number(a));
    csv.row_cells(cells);
    for (std::size_t j = 0; j < anatomical.size() && beyond_joint == anatomical.size(); ++j)
      if (std::abs(anatomical[j]) > std::numbers::pi) beyond_frame = k, beyond_joint = j, beyond_angle = anatomical[j];
  }
  if (beyond_joint < anatomical.size())
    warn(o,
         "{}: {} is {:.6g} degrees at the file's frame {} ({:.3f} s into the file), beyond +-180: the fit has "
         "gone a whole turn (360 degrees) from the angles before it, as it does after a bad frame (say, the root "
         "turned half a turn for one frame): check the clip around that frame (the filter spreads a bad frame "
         "over the frames around it)\n",
         clip_path, anatomical_joints[beyond_joint].name, beyond_angle * 180 / std::numbers::pi,
         marks.frame_number(beyond_frame), double(marks.frame_number(beyond_frame) - 1) * marks.frame_time);
  std::optional<AtomicFile> model_file;
  if (!model_out.empty()) {
    json::Json file = model_to_json(body);
    const double values[] = {m.body.foot_length, m.body.toe_drop, m.body.head_length, m.body.lower_back_length};
    for (std::size_t k = 0; k < landmark_keys.size(); ++k) file["landmarks"][std::string(landmark_keys[k])] = values[k];
    model_file.emplace(model_out);
    model_file->write(json::write(file));
  }
  commit_together({&csv.file(), model_file ? &*model_file : nullptr});
}

// Every .bvh of a folder (the extension in any case), on `threads` threads; a progress line on stderr, a
// summary of the failures.
int import_folder(const ImportCommandOptions& o) {
  std::vector<fs::path> clips;
  for (const auto& e : fs::directory_iterator(o.clip))  // (one that is not a file fails below, named)
    if (has_ending(e.path().filename().string(), ".bvh")) clips.push_back(e.path());
  std::sort(clips.begin(), clips.end());
  if (clips.empty()) throw UsageError("no .bvh file (in any case) in the folder " + text::shown(o.clip));
  for (std::size_t i = 0; i < clips.size(); ++i)  // a.bvh and a.BVH would write one a.csv
    for (std::size_t k = 0; k < i; ++k)
      if (clips[i].stem() == clips[k].stem())
        throw UsageError("the clips " + text::shown(clips[k].string()) + " and " + text::shown(clips[i].string()) +
                         " would both be written to " + text::shown(clips[i].stem().string()) + ".csv: rename one");
  if (const std::string fault = output_folder_fault(o.out); !fault.empty())
    throw UsageError("--out " + text::shown(o.out) + " is not a folder that can be made: " + fault);
  std::vector<std::string> outputs, inputs;
  for (const fs::path& clip : clips) {
    inputs.push_back(clip.string());
    for (const char* ending : {".csv", ".json"})
      outputs.push_back((fs::path(o.out) / (clip.stem().string() + ending)).string());
  }
  refuse_outputs(outputs, inputs);  // before any clip is imported
  MadeFolders made;                 // kept once a clip is in it: a run with no clip imported leaves none
  if (const std::string why = made.make(o.out); !why.empty())
    throw InputError("--out " + text::shown(o.out) + ": the folder cannot be made: " + why);

  std::atomic<std::size_t> next{0};
  std::vector<std::string> failures(clips.size());
  Progress progress;
  progress.terminal = ::isatty(STDERR_FILENO) != 0;
  progress.total = clips.size();
  ImportCommandOptions each = o;
  each.progress = &progress;
  const auto work = [&] {
    for (std::size_t i; (i = next++) < clips.size();) {
      const std::string stem = clips[i].stem().string();
      std::error_code ec;
      const fs::file_status status = fs::status(clips[i], ec);
      if (!fs::is_regular_file(status)) {  // a folder, a link to nothing or a pipe named CLIP.bvh: no clip
        failures[i] = fs::is_directory(status)                           ? "is a folder, not a clip"
                      : fs::exists(status)                               ? "is not a regular file"
                      : fs::is_symlink(fs::symlink_status(clips[i], ec)) ? "is a symbolic link to nothing"
                                                                         : "cannot be read: " + ec.message();
        progress.clip_done();
        continue;
      }
      try {
        import_one(clips[i].string(), (fs::path(o.out) / (stem + ".csv")).string(),
                   (fs::path(o.out) / (stem + ".json")).string(), each);
      } catch (const std::bad_alloc&) {
        failures[i] = "out of memory: the clip needs more memory than the process can have";
      } catch (const std::exception& e) {
        failures[i] = e.what();
      }
      progress.clip_done();
    }
  };
  const bool terminal = progress.terminal;
  const std::size_t n = std::min(clips.size(), std::size_t(o.threads > 0 ? o.threads : usable_cores()));
  std::vector<std::thread> pool;
  for (std::size_t t = 0; t < n; ++t) pool.emplace_back(work);
  for (auto& t : pool) t.join();
  if (terminal) cli::print(stderr, "\n");

  const auto failed = std::count_if(failures.begin(), failures.end(), [](const auto& f) { return !f.empty(); });
  if (std::size_t(failed) < clips.size()) made.keep();
  cli::print(stderr, "humandyn motion import: {} of {} clips imported into {}", clips.size() - std::size_t(failed),
             clips.size(), text::shown(o.out));
  if (failed == 0)
    cli::print(stderr, "\n");
  else
    cli::print(stderr, "; {} failed:\n", failed);
  for (std::size_t i = 0; i < clips.size(); ++i) {
    if (failures[i].empty()) continue;
    const std::string clip = clips[i].string();  // (most messages name the clip already)
    cli::print(stderr, "  {}\n", failures[i].starts_with(clip + ":") ? failures[i] : clip + ": " + failures[i]);
  }
  return failed == 0 ? 0 : 1;
}

int run_import(ImportCommandOptions o) {
  if (o.cmu) {
    o.unit = hm::cmu_metres_per_unit;
    o.up = hm::UpAxis::y;
    o.drop_first_frame = true;
  }
  // (a body's segments take fractions of it down to about 1e-3, their inertias 1e-5 of it in m^2: a normal
  // number for every mass of this range, which spans figurines to giants)
  if (!(o.mass >= 1e-3 && o.mass <= 1e4))
    throw UsageError("--mass must be from 0.001 to 10000 kg, got " + format_number(o.mass));
  if (o.model_given) o.given = given_body(o.model);
  if (o.cutoff < 0) throw UsageError("--cutoff must be 0 (no filter) or positive, got " + format_number(o.cutoff));
  if (o.threads < 0)
    throw UsageError("--threads must be 0 (every core it may run on) or positive, got " + std::to_string(o.threads));
  if (!(o.unit > 0)) throw UsageError("--unit must be positive, got " + format_number(o.unit));
  // (a CSV and a JSON document in turn: neither could be read), however standard output is named
  if (names_standard_output(o.out) && !o.model_out.empty() && names_standard_output(o.model_out))
    throw UsageError("--out " + text::shown(o.out) + " and --model-out " + text::shown(o.model_out) +
                     ": standard output takes one of them; give the other a file");
  const bool folder = fs::is_directory(o.clip);
  if (folder && !o.model_out.empty())
    throw UsageError("--model-out goes with one clip; a folder gets CLIP.json per clip");
  if (folder && o.out == "-")
    throw UsageError("--out - is standard output, which takes one clip; a folder needs a folder");
  try {  // (once, the usage checked, before any clip: a folder's clips share it)
    if (!o.map.empty()) o.landmarks = hm::read_landmark_map(o.map);
  } catch (const hm::BvhError& e) {
    throw InputError(e.what());
  }
  if (folder) return import_folder(o);
  try {
    import_one(o.clip, o.out, o.model_out, o);
  } catch (const hm::BvhError& e) {
    throw InputError(e.what());
  } catch (const hm::MotionError& e) {
    throw InputError(e.what());
  }
  return 0;
}

struct ExportCommandOptions {
  std::string in, out;
  ModelOptions model;
};

// The body --model names: its kinematics (a built-in body or a file of the seed's shape; its masses move no
// landmark) and, from a model file that has them (`motion import --model-out` writes them), its
// "landmarks"; else a foot 0.19 m long with the toe at the sole's level, the head 0.24 m above the neck,
// the lower back 0.10 m above the mid-hip point.
GivenBody given_body(const ModelOptions& options) {
  const std::string& name = options.model;
  ModelSource source = read_model(options);
  if (source.floating)
    throw UsageError(name +
                     " describes the floating form of a body; motion import and export take the "
                     "stance-rooted one (`humandyn model --json` without --floating writes it)");
  ModelDescription<double>& d = source.description;
  hm::ClipBody b;
  try {
    b.parameters = with_dimensions_of(d, default_parameters());
  } catch (const ModelError& e) {
    throw UsageError("motion import and export take a body of the seed's shape, which '" + name +
                     "' is not: " + e.what());
  }
  // the body stands as the built-in ones do (the fit's first guess and the stance forms take it so):
  // where a file's base pose put it at q = 0 does not matter here, the clip places it frame by frame
  b.parameters.base_pose = standing_base_pose(b.parameters);
  b.foot_length = 0.19;
  b.toe_drop = b.parameters.a16;
  b.head_length = 0.24;
  b.lower_back_length = 0.10;
  // the file's landmarks (model_from_json checked their form), each within the body's leg length
  if (source.landmarks) {
    const json::Node marks(*source.landmarks, name, "/landmarks");
    const double leg = b.parameters.a1 + b.parameters.a2;
    double* const values[] = {&b.foot_length, &b.toe_drop, &b.head_length, &b.lower_back_length};
    const double least[] = {0.05 * leg, -leg, 0, 0};
    for (std::size_t k = 0; k < landmark_keys.size(); ++k) {
      const json::Node v = marks.at(std::string(landmark_keys[k]));
      *values[k] = v.number();
      if (!(*values[k] >= least[k] && *values[k] <= leg))
        v.fail(fmt::format("{} m is outside {} .. {} m, the bounds the body's leg (a1 + a2 = {} m) sets",
                           exact_number(*values[k]), exact_number(least[k]), exact_number(leg), exact_number(leg)));
    }
    if (!(std::abs(b.toe_drop) < b.foot_length))
      marks.at("toe_drop")
          .fail(fmt::format("the toe {} m below the ankle is beyond the foot's length, {} m", exact_number(b.toe_drop),
                            exact_number(b.foot_length)));
  } else if (!(b.toe_drop < b.foot_length)) {
    throw UsageError(
        fmt::format("'{}': an ankle {} m above the sole is beyond the 0.19 m foot drawn without a model file's "
                    "\"landmarks\"",
                    name, exact_number(b.toe_drop)));
  }
  return {std::move(d), b};
}

// Landmarks as a BVH clip (metres, Y up, the BVH default): a root `Hips` at the mid-hip point and under it one
// joint per landmark, named as the built-in landmark map reads it, with position channels only, so that each
// joint stands exactly at its landmark.
hm::BvhClip landmarks_bvh(const hm::LandmarkClip& clip) {
  using enum hm::Landmark;
  const std::vector<std::pair<hm::Landmark, const char*>> names{
      {r_hip, "RightUpLeg"},     {r_knee, "RightLeg"},   {r_ankle, "RightFoot"},  {r_toe, "RightToeBase"},
      {l_hip, "LeftUpLeg"},      {l_knee, "LeftLeg"},    {l_ankle, "LeftFoot"},   {l_toe, "LeftToeBase"},
      {lower_back, "Spine"},     {neck, "Neck"},         {head, "Head"},          {r_shoulder, "RightArm"},
      {r_elbow, "RightForeArm"}, {r_wrist, "RightHand"}, {l_shoulder, "LeftArm"}, {l_elbow, "LeftForeArm"},
      {l_wrist, "LeftHand"}};
  const std::vector<hm::Channel> xyz{hm::Channel::Xposition, hm::Channel::Yposition, hm::Channel::Zposition};
  hm::BvhClip b;
  b.frame_time = clip.frame_time;
  b.joints.push_back({"Hips", -1, Eigen::Vector3d::Zero(), xyz});
  for (const auto& n : names) b.joints.push_back({n.second, 0, Eigen::Vector3d::Zero(), xyz});
  const auto put = [&](const Eigen::Vector3d& w) {  // world (x forward, y left, z up) to Y-up file (y, z, x)
    b.values.insert(b.values.end(), {w.y(), w.z(), w.x()});
  };
  for (const hm::LandmarkFrame& f : clip.frames) {
    const Eigen::Vector3d mid = 0.5 * (f[std::size_t(r_hip)] + f[std::size_t(l_hip)]);
    put(mid);
    for (const auto& n : names) put(f[std::size_t(n.first)] - mid);
  }
  return b;
}

int run_export(const ExportCommandOptions& o) {
  const GivenBody given = given_body(o.model);
  const hm::ClipBody& body = given.body;
  const HumanModel<double> right = human_model(body.parameters);
  const AnyModel<double> model(right.description());
  Data<AnyModel<double>> data(model);
  const hm::Fitter fitter(body);
  const StanceSwitch<HumanModel<double>, hm::FloatingModel> to_floating(right, fitter.model());

  // the columns id reads: the right-stance model's q_, the base's, the stance foot; qd_, qdd_, phase and
  // any other column passed over (a misspelt q_, qd_, qdd_, tau_ or base_ column is an error)
  const std::vector<std::string> names = joint_names(right.description());
  std::vector<ColumnGroup> groups{{joint_columns(names, "q_"), ColumnGroup::Required},
                                  {joint_columns(names, "qd_"), ColumnGroup::Ignored},
                                  {joint_columns(names, "qdd_"), ColumnGroup::Ignored}};
  const BaseColumns base_columns(groups);
  const JointTable states(o.in, groups, {"q_", "qd_", "qdd_", "tau_", "base_"}, {"stance", "phase"},
                          StateForm::StanceRooted);
  if (!states.has_time()) throw InputError(states.csv().source + ": missing column 't' (the clip's frame time)");
  if (states.rows() < 2)
    throw InputError(states.csv().source + ": a clip needs 2 rows or more, the file has " +
                     std::to_string(states.rows()));
  hm::LandmarkClip clip;
  clip.source = states.csv().source;
  clip.frame_time = states.time(1) - states.time(0);
  if (!(clip.frame_time > 0)) states.fail_at(1, "t", "the time must grow from row to row");
  if (!std::isfinite(clip.frame_time))  // (two times near double's ends)
    states.fail_at(
        1, "t", "the time step from the first row, " + exact_number(states.time(0)) + " s, is beyond double's range");
  for (std::size_t r = 2; r < states.rows(); ++r)  // a BVH clip has one frame time
    if (const double step = states.time(r) - states.time(r - 1);
        !(std::abs(step - clip.frame_time) <= 1e-6 * clip.frame_time))
      states.fail_at(r, "t",
                     fmt::format("the time step is {} s here and {} s from the first row to the second: a BVH clip "
                                 "has one frame time",
                                 exact_number(step), exact_number(clip.frame_time)));

  // each row's body where it stands (as `view` places it), its landmarks where the fit's floating body
  // puts them; rows without the stance foot's pose start where the model's base pose puts the body (the
  // standing body the fit uses, moved there)
  StancePlacement where(model, base_columns, states, given.description.base_pose * body.parameters.base_pose.inverse());
  const HumanModel<double>::JointVector zero = HumanModel<double>::JointVector::Zero();
  Eigen::VectorXd q(16);
  for (std::size_t r = 0; r < states.rows(); ++r) {
    states.read(r, 0, q);
    forward_kinematics(model, data, q);
    const Pose<double> placement = where.at(r, StanceSwitching::left_row(states, r), data);
    StanceState<hm::FloatingModel> f;
    to_floating(right, fitter.model(), HumanModel<double>::JointVector(q), zero, f);
    clip.frames.push_back(fitter.landmarks(placement * f.base_pose, f.q));
    // (a clip that motion import would take back: landmarks within 1e6 m of the origin)
    if (const int l = hm::first_unusable_landmark(clip.frames.back()); l >= 0)
      throw InputError(
          fmt::format("{}: line {}: the body this row places has landmark '{}' at {} m, beyond {} m "
                      "of the origin (the base position?)",
                      states.csv().source, states.csv().lines.at(r), hm::landmark_names[std::size_t(l)],
                      exact_number(clip.frames.back()[std::size_t(l)].cwiseAbs().maxCoeff<Eigen::PropagateNaN>()),
                      exact_number(hm::max_landmark_coordinate)));
  }
  write_file_atomically(o.out, hm::to_bvh(landmarks_bvh(clip)));
  return 0;
}

// `motion import` and its options.
Command add_import(CLI::App& motion) {
  const auto o = std::make_shared<ImportCommandOptions>();
  CLI::App* c = motion.add_subcommand(
      "import",
      "a BVH clip (or every .bvh of a folder) fitted, filtered and split by stance foot\n\n"
      "Reads the clip's joint centres, scales the body to them (de Leva's segments, --mass), fits its joint\n"
      "angles and pelvis per frame, filters (zero-lag Butterworth, --cutoff) and differentiates, finds the\n"
      "feet's contact phases and writes, per frame, the states of the body rooted at the stance foot with\n"
      "that foot's motion as its base: the input of `humandyn id --model BODY.json` (docs/motion.md).");
  c->add_option("CLIP", o->clip, "a BVH file, or a folder: every .bvh in it (any case), across all cores")->required();
  c->add_option("--out", o->out,
                "the states (CSV): t, phase (right, left, double, flight), stance (right,\n"
                "left), base_x.. base_qw.. base_wx.. base_wdx.. base_ax.. (the stance foot's\n"
                "ankle frame, world), q_, qd_, qdd_ of the right-stance model's joints, and the\n"
                "anatomical angles (rad; r_knee_flexion, ...). For a folder: a folder,\n"
                "CLIP.csv and CLIP.json (the scaled body) per clip")
      ->option_text("FILE|FOLDER")
      ->required();
  c->add_option("--model-out", o->model_out,
                "the body scaled to the clip (or given), as `humandyn model --json` writes\n"
                "it, with the landmark geometry the fit measured (`motion export --model` reads it);\n"
                "'-' for standard output, where --out is a file")
      ->option_text("FILE.json");
  CLI::Option* mass = add_number(*c, "--mass", o->mass, "the body's mass, kg (default 70)");
  CLI::Option* model =
      c->add_option("--model", o->model.model,
                    "the body to fit the clip with instead of one scaled to it: " + builtin_model_names(", ", ", ") +
                        ",\n"
                        "or a FILE.json or FILE.urdf of the seed's shape (a FILE.json as\n"
                        "--model-out writes it brings the foot, head and lower back it measured; the\n"
                        "others get a 0.19 m foot, which turns the ankle angles if the clip's differs);\n"
                        "a FILE.urdf imported with --root, --joints and --balance-inertia (the clip\n"
                        "gives the world's up; the fit takes the body's lengths)")
          ->option_text("M")
          ->excludes(mass)
          ->each([o](const std::string&) { o->model_given = true; });
#ifdef HUMANDYN_WITH_URDF
  add_urdf_options(*c, o->model.urdf, "the model (a FILE.urdf)", false);
  for (const char* name : {"--root", "--joints", "--balance-inertia"}) c->get_option(name)->needs(model);
#else
  (void)model;
#endif
  add_number(*c, "--cutoff", o->cutoff, "the low-pass cut-off, Hz (default 6; 0: no filter)");
  c->add_option("--map", o->map, "a landmark map file: BVH joints for the body's landmarks (docs/motion.md)")
      ->option_text("FILE");
  CLI::Option* unit = add_number(*c, "--unit", o->unit, "metres per file unit (default 1)");
  CLI::Option* up =
      add_choice(*c, "--up", o->up, {{"y", hm::UpAxis::y}, {"z", hm::UpAxis::z}}, "the file's up axis (default y)");
  CLI::Option* drop =
      c->add_flag("--drop-first-frame", o->drop_first_frame, "leave out the clip's first frame (an added T-pose)");
  c->add_flag("--cmu", o->cmu,
              "CMU's clips in Hahne's conversion: the unit 0.0254 / 0.45 m (0.0564444...),\n"
              "--up y and --drop-first-frame (not given beside them)")
      ->excludes(unit)
      ->excludes(up)
      ->excludes(drop);
  add_whole_number(*c, "--threads", o->threads,
                   "threads for a folder, 0 for every core the process may run on (default 0)");
  return {c, [o] { return run_import(*o); }};
}

// `motion export` and its options.
Command add_export(CLI::App& motion) {
  const auto o = std::make_shared<ExportCommandOptions>();
  CLI::App* c = motion.add_subcommand(
      "export",
      "a body's motion written as a BVH clip of its landmarks\n\n"
      "Reads the right-stance q_ columns of STATES.csv (and, when there, the stance foot's pose base_x..,\n"
      "base_qw.. and the stance column, as `motion import` writes them) and writes a BVH clip whose joints\n"
      "stand at the body's joint centres and landmarks: `motion import CLIP.bvh` reads the same angles back.\n"
      "The body is a built-in one or a model file of the seed's shape, such as `motion import --model-out`\n"
      "writes (its lengths from its DH rows; its masses move no landmark).");
  c->add_option("STATES", o->in, "the states (CSV), '-' for standard input")->required();
  c->add_option("--out", o->out, "the BVH clip (metres, Y up, the frame time from the t column)")
      ->option_text("FILE.bvh")
      ->required();
  add_model_options(*c, o->model);
  return {c, [o] { return run_export(*o); }};
}

}  // namespace

Command add_motion(CLI::App& humandyn) {
  CLI::App* motion = humandyn.add_subcommand("motion", "motion capture in: BVH clips to the states `id` reads");
  motion->require_subcommand(1);
  const Command import_command = add_import(*motion);
  const Command export_command = add_export(*motion);
  return {motion, [import_command, export_command] {
            return import_command.app->parsed() ? import_command.run() : export_command.run();
          }};
}

}  // namespace humandyn::cli
