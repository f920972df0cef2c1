// libFuzzer target: the model-JSON reader (`--model FILE.json`) fed arbitrary bytes. Every input must
// give a model or one of the reader's documented errors: humandyn::cli::InputError (syntax, with line and
// column; a missing or malformed entry, with its key) or humandyn::ModelError (a description the library
// refuses). A model it gives must write back to JSON that reads back to the same description. A crash, a
// hang, a sanitizer report or any other exception is a bug. Seeds: tests/data/fuzz/model_json/.
#include "cli/errors.hpp"
#include "cli/model_json.hpp"
#include "humandyn/model.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto description = humandyn::cli::parse_model_json(text, "fuzz.json");
    const humandyn::AnyModel<double> model(description);
    const auto again = humandyn::cli::parse_model_json(humandyn::cli::write_model_json(description), "fuzz-out.json");
    if (again.joints.size() != description.joints.size()) std::abort();
  } catch (const humandyn::cli::InputError&) {
  } catch (const humandyn::ModelError&) {
  }
  return 0;
}
