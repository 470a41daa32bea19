#pragma once
// The robustness sweep's report (docs/evaluation.md, "Robustness sweep"): the
// same trials run at a ladder of error levels (`sva simulate --error-scale X`,
// then train and eval at each), summarised against the error level: a table
// and a figure of accuracy and median pose errors at a few reading counts.
#include <filesystem>
#include <string>
#include <vector>

#include <sva/eval/results.hpp>

namespace sva::eval {

struct SweepLevel {
  double scale = 0.0;  // x the scene's realistic errors (0: the ideal world)
  Curve curve;         // that level's eval summary
};

// Parses "X=FILE.json" (the --sweep option) and reads the summary. Throws
// sva::Error naming the argument or the file.
SweepLevel read_sweep_level(const std::string& argument);

// Checks that the levels are one sweep: at least one, distinct scales, the same
// scene, method and trial count, and curves long enough for every reading
// count in `readings` (non-empty, each >= 1). Sorts them by scale.
void check_sweep(std::vector<SweepLevel>& levels, const std::vector<std::size_t>& readings);

// A Markdown table: one row per level; accuracy at each reading count, then
// the median (and mean) translation, angle and inertial errors at each.
std::string format_sweep_table(const std::vector<SweepLevel>& levels, const std::vector<std::size_t>& readings);

// Four panels like the eval figure's, with the error level on the x axis and
// one curve per reading count. Written atomically as PNG.
void write_sweep_figure(const std::vector<SweepLevel>& levels, const std::vector<std::size_t>& readings,
                        const std::filesystem::path& file);

}  // namespace sva::eval
