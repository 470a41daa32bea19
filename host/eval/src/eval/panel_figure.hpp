#pragma once
// The 2 x 2 panels of the evaluation figure (sva/eval/figure.hpp), drawn for any series: the figure's curves
// against readings, or a robustness sweep's curves against the error level.
#include <sva/eval/results.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

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

}  // namespace sva::eval
