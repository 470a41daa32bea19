#include <sva/eval/robustness.hpp>
#include "eval/table_cell.hpp"

#include <sva/error.hpp>
#include <sva/eval/figure.hpp>
#include <sva/eval/report.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "eval/panel_figure.hpp"
#include "plot/canvas.hpp"

namespace sva::eval {

namespace {

const CurvePoint& point_at(const Curve& c, std::size_t readings) { return c.points[readings - 1]; }

std::string scale_text(double scale) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", scale);
  return buf;
}

}  // namespace

SweepLevel read_sweep_level(const std::string& argument) {
  const auto eq = argument.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == argument.size())
    throw Error("--sweep \"" + argument + "\": expected LEVEL=FILE.json (e.g. 0.5=level0.5/eval.json)");
  const std::string level = argument.substr(0, eq);
  char* end = nullptr;
  const double scale = std::strtod(level.c_str(), &end);
  if (*end != '\0' || !std::isfinite(scale) || scale < 0)
    throw Error("--sweep \"" + argument + "\": the level \"" + level + "\" is not a finite number >= 0");
  return {scale, read_curve_json(argument.substr(eq + 1))};
}

void check_sweep(std::vector<SweepLevel>& levels, const std::vector<std::size_t>& readings) {
  if (levels.empty()) throw Error("robustness sweep: no levels to report");
  if (readings.empty()) throw Error("robustness sweep: no reading counts to report");
  std::sort(levels.begin(), levels.end(), [](const auto& a, const auto& b) { return a.scale < b.scale; });
  const Curve& first = levels.front().curve;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const Curve& c = levels[i].curve;
    const std::string what = "robustness sweep: level " + scale_text(levels[i].scale);
    if (i > 0 && levels[i].scale == levels[i - 1].scale) throw Error(what + " is given twice");
    if (c.scene != first.scene || c.method != first.method || c.trials != first.trials)
      throw Error(what + " is from another run (" + c.scene + ", " + c.method + ", " + std::to_string(c.trials) +
                  " trials) than level " + scale_text(levels.front().scale) + " (" + first.scene + ", " + first.method +
                  ", " + std::to_string(first.trials) + " trials)");
    for (std::size_t r : readings)
      if (r < 1 || r > c.points.size() || c.points[r - 1].readings != r)
        throw Error(what + " has no point at " + std::to_string(r) + " readings (its curve has " +
                    std::to_string(c.points.size()) + ")");
  }
}

std::string format_sweep_table(const std::vector<SweepLevel>& levels, const std::vector<std::size_t>& readings) {
  std::string head = "| error level |", rule = "|---|";
  for (std::size_t r : readings) head += " acc " + std::to_string(r) + " |", rule += "---|";
  for (std::size_t r : readings)
    head += " trans / angle / inertial at " + std::to_string(r) + " (median; mean) |", rule += "---|";
  std::string out = head + "\n" + rule + "\n";
  for (const auto& l : levels) {
    std::string row = "| " + scale_text(l.scale) + " |";
    for (std::size_t r : readings) row += " " + cell(100.0 * point_at(l.curve, r).accuracy, "%.1f%%") + " |";
    for (std::size_t r : readings) {
      const CurvePoint& p = point_at(l.curve, r);
      row += " " + cell(p.translation_mm.median, "%.2f") + " mm / " + cell(p.angular_deg.median, "%.2f") + "° / " +
             cell(p.inertial_mm.median, "%.2f") + " mm; " + cell(p.translation_mm.mean, "%.2f") + " / " +
             cell(p.angular_deg.mean, "%.1f") + " / " + cell(p.inertial_mm.mean, "%.2f") + " |";
    }
    out += row + "\n";
  }
  return out;
}

void write_sweep_figure(const std::vector<SweepLevel>& levels, const std::vector<std::size_t>& readings,
                        const std::filesystem::path& file) {
  if (levels.empty()) throw Error(file.string() + ": no levels to plot");
  const Curve& first = levels.front().curve;
  const std::string title =
      first.scene + ": robustness sweep, " + first.method + " (" + std::to_string(first.trials) + " trials per level)";
  const double x_max = std::max(levels.back().scale, 1e-9);
  write_panel_figure(
      title, "error level (x the scene's realistic errors)", x_max,
      [&](const Panel& panel) {
        std::vector<plot::Series> series;
        for (std::size_t i = 0; i < readings.size(); ++i) {
          plot::Series s;
          s.label = std::to_string(readings[i]) + " readings";
          s.color = plot::palette(i);
          for (const auto& l : levels) {
            s.x.push_back(l.scale);
            s.y.push_back(panel.get(point_at(l.curve, readings[i])));
          }
          series.push_back(std::move(s));
        }
        return series;
      },
      file);
}

}  // namespace sva::eval
