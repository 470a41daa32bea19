#pragma once
// The evaluation figure, laid out like the paper's Fig. 4 and 5: classification
// accuracy, inertial, translational and angular error against the number of
// readings, every curve (e.g. SVA and the appearance-only baseline) on the
// same axes. Curves without pose errors (the baseline) appear only in the
// accuracy panel.
#include <sva/eval/results.hpp>

#include <filesystem>
#include <vector>

namespace sva::eval {

// Writes a PNG (atomically). Throws sva::Error when `curves` is empty or the
// file cannot be written.
void write_figure(const std::vector<Curve>& curves, const std::filesystem::path& file);
// The reliability diagram of a run (Curve::calibration): the share right against the top object's probability,
// per bin, beside the diagonal of perfect calibration.
void write_reliability_figure(const Curve& curve, const std::filesystem::path& file);

}  // namespace sva::eval
