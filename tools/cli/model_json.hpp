// A model description as JSON, the format `humandyn model --json` prints and `--model FILE.json`
// reads: everything needed to rebuild the model in another library, with its conventions stated in
// the file itself.
//
//   {
//     "format": "humandyn-model", "version": 1, "name": "...",
//     "conventions": { "units": "...", "dh": "...", ... },          (for the reader of the file; ignored)
//     "gravity": [0, 0, -9.81],                                     (world frame; optional, this default)
//     "base": { "joint": "floating",                               (optional: the floating form; else fixed)
//               "pose": {"R": [[...], [...], [...]], "p": [x, y, z]},  (optional: identity pose, massless)
//               "link": {"name": "r_foot", "mass": m, "com": [...], "inertia": [[...], [...], [...]]} },
//     "joints": [
//       { "index": 0, "name": "r_ankle_pitch", "parent": -1,
//         "mount": {"R": ..., "p": ...},                           (optional; a 4x4 matrix is accepted too)
//         "dh": {"a": m, "alpha": rad, "d": m, "theta": rad},
//         "link": {"name": "r_shank", "mass": kg, "com": [m, m, m], "inertia": [[kg m^2 ...], ...]} },
//       ...
//     ],
//     "landmarks": {"foot_length": m, "toe_drop": m, "head_length": m, "lower_back_length": m}
//                              (optional: the landmark geometry of a body `motion import` scaled to a clip,
//                               which `motion export` and `motion import --model` read; checked here for
//                               its form only)
//   }
//
// Numbers are written in the shortest form that reads back to the same double, so a model written
// and read back gives bit-identical torques. Errors: InputError naming the file and the line and column
// of a syntax error, or the JSON path of a missing or malformed entry ("m.json: /joints/3/dh/a: must be
// a number, not a string").
#pragma once

#include "cli/json.hpp"
#include "humandyn/model.hpp"

#include <array>
#include <string>
#include <string_view>

namespace humandyn::cli {

// Degrees per radian: the DH tables that `model` and `urdf2dh` print give their angles in degrees.
inline constexpr double rad_to_deg = 57.295779513082320876798;

// The numbers of a model file's "landmarks" (m): ankle to toe, the toe's drop below the ankle with the foot
// flat, neck to head, mid-hip point to lower back (0: none usable).
inline constexpr std::array<std::string_view, 4> landmark_keys{"foot_length", "toe_drop", "head_length",
                                                               "lower_back_length"};

// The description as a JSON document; `floating`: the base is free (6-DOF), "base": {"joint": "floating"}.
json::Json model_to_json(const ModelDescription<double>& model, bool floating = false);

// A description from a JSON document (`source` names it in messages); InputError naming the path of a
// missing or malformed entry. Physical validity (masses, inertias, rotations) is checked when a Model
// is built. `floating` receives whether the file describes a floating base; without it, such a file
// is an InputError (the caller reads fixed bases only).
ModelDescription<double> model_from_json(const json::Json& document, const std::string& source,
                                         bool* floating = nullptr);

// A description from JSON text; `source` names it in messages. InputError as model_from_json.
ModelDescription<double> parse_model_json(std::string_view text, const std::string& source, bool* floating = nullptr);

// Reads a model file. InputError if it cannot be read, parsed or understood.
ModelDescription<double> read_model_json(const std::string& path, bool* floating = nullptr);

// The description as JSON text (what `humandyn model --json [--floating]` prints).
std::string write_model_json(const ModelDescription<double>& model, bool floating = false);

}  // namespace humandyn::cli
