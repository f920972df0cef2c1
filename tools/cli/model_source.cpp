#include "cli/model_source.hpp"

#include "humandyn/builders.hpp"

namespace humandyn::cli {

ModelDescription<double> load_model(Args& args) {
  const std::string name = args.get_or("--model", "default");
  if (name == "default") return human_description(default_parameters());
  if (name == "female") return human_description(female_parameters());
  if (name == "paper") return human_description(paper_parameters());
  throw UsageError("unknown model '" + name + "' (expected " + builtin_models + ")");
}

}  // namespace humandyn::cli
