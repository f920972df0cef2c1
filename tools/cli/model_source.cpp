#include "cli/model_source.hpp"

#include "cli/model_json.hpp"
#include "cli/urdf_source.hpp"
#include "humandyn/builders.hpp"

namespace humandyn::cli {

ModelDescription<double> load_model(Args& args) {
  const std::string name = args.get_or("--model", "default");
  if (name == "default") return human_description(default_parameters());
  if (name == "female") return human_description(female_parameters());
  if (name == "paper") return human_description(paper_parameters());
#ifdef HUMANDYN_WITH_URDF
  // a URDF file, imported as DH chains (--root, --joints, --up or --gravity, --balance-inertia go with it)
  if (is_urdf_path(name)) return import_urdf_args(args, name).model;
#endif
  // a model file written by `humandyn model --json` (or by hand in that format)
  if (name.size() > 5 && name.compare(name.size() - 5, 5, ".json") == 0) return read_model_json(name);
  throw UsageError("unknown model '" + name + "' (expected " + builtin_models + " or a FILE.json or FILE.urdf)");
}

std::string model_options_help() {
#ifdef HUMANDYN_WITH_URDF
  return "  --model M        default, female or paper (built in; default: default, de Leva's reference male), a\n"
         "                   FILE.json written by `humandyn model --json`, or a FILE.urdf, imported with:\n" +
         std::string(urdf_options_help);
#else
  return "  --model M        default, female or paper (built in; default: default, de Leva's reference male) or a\n"
         "                   FILE.json written by `humandyn model --json`\n";
#endif
}

}  // namespace humandyn::cli
