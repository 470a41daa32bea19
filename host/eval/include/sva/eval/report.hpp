#pragma once
// Evaluation reports: the JSON summary (schema in docs/evaluation.md), the
// per-step CSV, the stdout table, and reading a JSON summary back (for
// overlaying another run in a plot). Write files with io::write_text_file.
#include <filesystem>
#include <string>

#include <sva/eval/results.hpp>
#include <sva/map.hpp>

namespace sva::eval {

// {"scene", "backend", "method", "trials", "seed", "max_readings", "objects",
//  "curve": [{"readings", "accuracy", "pose_trials", "translation_error_mm", "angular_error_deg",
//             "inertial_error_mm", "mssd_mm", "adds_mm", "update_ms" (medians; each also with _mean and _p90;
//             MSSD and ADD-S null without the objects' meshes, docs/pose-errors.md),
//             "update_ms_p95", "votes", "votes_zero"}]}
// Everything but the update_ms* fields depends only on the inputs and seed.
std::string to_json(const EvalResult& result, const Curve& curve);
// One row per (trial, readings).
std::string to_csv(const EvalResult& result);
// One JSON object a line per (trial, readings): what each estimate's object posterior was made of, to weigh it
// otherwise offline (docs/evaluation.md, "The evidence behind each answer"): {"trial", "readings", "object" (the
// test set's name), "map_object" (the truth's id in the map, null when the map lacks it), "estimated_object",
// "correct", "temperature", "surface_weight", "pairs_log2_mass", "surface_log2_fit"} (arrays indexed by map object id;
// empty unless the run kept them: EvalOptions::keep_evidence).
std::string to_evidence_jsonl(const EvalResult& result);
// The curve as a fixed-width table (readings, accuracy, errors, ms/update).
std::string format_table(const Curve& curve);

// One line on a map's calibration (sva train, sva inspect): learned or the default, the temperature's law and
// whether it can say "none of these".
std::string describe_calibration(const MapSummary& map);
// One line on a map's surfaces (sva train, sva inspect): what the verify stage weighs the readings against, the
// meshes (their triangles and bytes, apart from the entries') or the training contacts.
std::string describe_surfaces(const MapSummary& map);

// Reads a JSON summary written by to_json; errors name the file and field.
Curve read_curve_json(const std::filesystem::path& file);

}  // namespace sva::eval
