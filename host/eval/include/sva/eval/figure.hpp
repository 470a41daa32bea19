#pragma once
// The evaluation figure, laid out like the paper's Fig. 4 and 5: classification
// accuracy, inertial, translational and angular error against the number of
// readings, every curve (e.g. SVA and the appearance-only baseline) on the
// same axes. Curves without pose errors (the baseline) appear only in the
// accuracy panel.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <sva/eval/results.hpp>
#include "plot/canvas.hpp"

namespace sva::eval {

// One of the figure's four panels: what it plots of a curve point.
struct Panel {
  const char* title;
  const char* y_label;
  double (*get)(const CurvePoint&);  // NaN where the point has no value
  bool percent;                      // 0-100 axis; otherwise 0 to 1.1 x the largest value
};
// Accuracy, inertial, translational and angular error (the paper's panels).
const std::vector<Panel>& panels();

// The four panels in a 2 x 2 grid under `title`, each with the series
// `series_of` gives for it, over [0, x_max]. Writes a PNG (atomically).
void write_panel_figure(const std::string& title, const std::string& x_label, double x_max,
                        const std::function<std::vector<plot::Series>(const Panel&)>& series_of,
                        const std::filesystem::path& file);

// Writes a PNG (atomically). Throws sva::Error when `curves` is empty or the
// file cannot be written.
void write_figure(const std::vector<Curve>& curves, const std::filesystem::path& file);

}  // namespace sva::eval
