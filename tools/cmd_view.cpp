// humandyn view: a clip of states (and its torques) as one self-contained HTML page that plays it.
#include "cli/atomic_file.hpp"
#include "cli/commands.hpp"
#include "cli/model_source.hpp"
#include "cli/options.hpp"
#include "cli/view_page.hpp"

#include <algorithm>
#include <memory>
#include <optional>
#include <string>

namespace humandyn::cli {

namespace {

struct ViewOptions {
  ModelOptions model;
  ViewInputs inputs;
  std::optional<std::string> plot;
  std::string out;
};

int run_view(ViewOptions o) {
  if (o.plot) {  // JOINT,JOINT,...: no empty name (so '' and a trailing comma are refused), none twice
    for (std::size_t start = 0;;) {
      const std::size_t end = std::min(o.plot->find(',', start), o.plot->size());
      if (end == start) throw UsageError("--plot: an empty joint name in '" + shown(*o.plot) + "'");
      std::string name = o.plot->substr(start, end - start);
      if (std::find(o.inputs.plot.begin(), o.inputs.plot.end(), name) != o.inputs.plot.end())
        throw UsageError("--plot: joint '" + shown(name) + "' given twice in '" + shown(*o.plot) + "'");
      o.inputs.plot.push_back(std::move(name));
      if (end == o.plot->size()) break;
      start = end + 1;
    }
  }
  const ViewClip clip = load_view_clip(o.inputs, load_model(o.model));
  write_file_atomically(o.out, view_page(clip));
  return 0;
}

}  // namespace

Command add_view(CLI::App& humandyn) {
  const auto o = std::make_shared<ViewOptions>();
  CLI::App* c = humandyn.add_subcommand(
      "view",
      "a clip as one HTML page that plays it: front and side views, torques, ground reaction, time plot\n\n"
      "Places every link of every row of STATES.csv by forward kinematics and writes one HTML page, with no\n"
      "external resource, that plays the motion in a front view and a side view side by side (play, pause,\n"
      "a scrubber, a frame counter; space and the arrow keys too), each joint coloured by the magnitude of\n"
      "its torque when --torques is given, the ground reaction drawn at its centre of pressure when the\n"
      "torques file has it, and a time plot of the angles (and torques) of the joints picked below it.\n\n"
      "  humandyn motion import clip.bvh --cmu --out states.csv --model-out body.json\n"
      "  humandyn id --ground-reaction --model body.json --in states.csv --out tau.csv\n"
      "  humandyn view states.csv --torques tau.csv --model body.json --out clip.html");
  add_model_options(*c, o->model);
  c->add_option("states", o->inputs.states,
                "the states, the columns id reads (motion import writes them):\n"
                "q_<joint> (rad) for every joint, the model's angles on every row;\n"
                "optional t (s), stance (the foot the body stands on, held still:\n"
                "right, left, r or l), the stance foot's ankle frame base_x, base_y,\n"
                "base_z (m), base_qw, base_qx, base_qy, base_qz (unit quaternion,\n"
                "world), and phase (shown with its frame); other columns (qd_, qdd_,\n"
                "anatomical angles, ...) are passed over. '-' for standard input")
      ->option_text("STATES.csv")
      ->required();
  c->add_option("--torques", o->inputs.torques,
                "the torques of the same rows, as id [--ground-reaction] writes them:\n"
                "tau_<joint> (N m) for any joints; optional ground reaction grf_fx,\n"
                "grf_fy, grf_fz (N, world) drawn at its centre of pressure cop_x, cop_y,\n"
                "cop_z (m, world; empty where the foot pulls: no arrow)")
      ->option_text("FILE");
  c->add_option_function<std::string>(
       "--plot", [o](const std::string& text) { o->plot = text; },
       "the joints plotted at first, each once, e.g. r_knee_pitch,l_knee_pitch\n"
       "(default: the knees, or a body's first two joints where it has none); the\n"
       "page has a picker for the others")
      ->option_text("J,...");
  const CLI::Option* rate =
      add_number(*c, "--rate", o->inputs.rate,
                 "rows per second when STATES has no column t (default 100; refused\nwhere it has one)")
          ->option_text("HZ");
  c->add_option("--title", o->inputs.title, "the page's heading (default: the file and the model)")
      ->option_text("TEXT");
  c->add_option("--out", o->out, "the page (HTML), written all or nothing")->option_text("FILE")->required();
  return {c, [o, rate] {
            o->inputs.rate_given = rate->count() > 0;
            return run_view(*o);
          }};
}

}  // namespace humandyn::cli
