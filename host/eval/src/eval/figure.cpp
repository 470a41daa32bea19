#include <sva/eval/figure.hpp>

#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "eval/panel_figure.hpp"
#include "plot/canvas.hpp"

namespace sva::eval {

namespace {

constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

double value(const std::optional<double>& v) { return v ? *v : kMissing; }

}  // namespace

const std::vector<Panel>& panels() {
  static const std::vector<Panel> p = {
      {"(a) classification accuracy", "accuracy (%)", [](const CurvePoint& c) { return 100.0 * c.accuracy; }, true},
      {"(b) inertial error", "median inertial distance (mm)",
       [](const CurvePoint& c) { return value(c.inertial_mm.median); }, false},
      {"(c) translational error", "median |T_hat - T| (mm)",
       [](const CurvePoint& c) { return value(c.translation_mm.median); }, false},
      {"(d) angular error", "median angle (deg)", [](const CurvePoint& c) { return value(c.angular_deg.median); },
       false},
      // The symmetry-aware surface errors (docs/pose-errors.md): empty without the objects' meshes.
      {"(e) MSSD (symmetry-aware)", "median MSSD (mm)", [](const CurvePoint& c) { return value(c.mssd_mm.median); },
       false},
      {"(f) ADD-S", "median ADD-S (mm)", [](const CurvePoint& c) { return value(c.adds_mm.median); }, false},
  };
  return p;
}

void write_panel_figure(const std::string& title, const std::string& x_label, double x_max,
                        const std::function<std::vector<plot::Series>(const Panel&)>& series_of,
                        const std::filesystem::path& file) {
  constexpr int kPanelW = 620, kPanelH = 430, kHeader = 34;
  const int rows = static_cast<int>((panels().size() + 1) / 2);
  plot::Canvas canvas(2 * kPanelW, rows * kPanelH + kHeader);
  canvas.text((canvas.width() - plot::Canvas::text_width(title, 2)) / 2, 10, title, plot::kBlack, 2);
  for (std::size_t k = 0; k < panels().size(); ++k) {
    const Panel& panel = panels()[k];
    const std::vector<plot::Series> series = series_of(panel);
    plot::ChartOptions o;
    o.title = panel.title;
    o.x_label = x_label;
    o.y_label = panel.y_label;
    o.x_min = 0.0;
    o.x_max = x_max;
    o.y_min = 0.0;
    if (panel.percent) {
      o.y_max = 100.0;
    } else {
      // Headroom above the largest error so the curve does not run along the frame.
      double top = 0.0;
      for (const auto& s : series)
        for (double v : s.y)
          if (std::isfinite(v)) top = std::max(top, v);
      if (top > 0.0) o.y_max = 1.1 * top;
    }
    const int col = static_cast<int>(k % 2), row = static_cast<int>(k / 2);
    line_chart(canvas, col * kPanelW, kHeader + row * kPanelH, kPanelW, kPanelH, series, o);
  }
  canvas.write_figure(file);
}

void write_figure(const std::vector<Curve>& curves, const std::filesystem::path& file) {
  if (curves.empty()) throw Error(file.string() + ": no curves to plot");
  std::string title = curves.front().scene + ": ";
  for (std::size_t i = 0; i < curves.size(); ++i)
    title += (i ? ", " : "") + curves[i].label + " (" + std::to_string(curves[i].trials) + " trials)";
  double max_readings = 1.0;
  for (const auto& c : curves)
    for (const auto& p : c.points) max_readings = std::max(max_readings, static_cast<double>(p.readings));
  write_panel_figure(
      title, "number of readings", max_readings,
      [&](const Panel& panel) {
        std::vector<plot::Series> series;
        for (std::size_t i = 0; i < curves.size(); ++i) {
          plot::Series s;
          s.label = curves[i].label;
          s.color = plot::palette(i);
          s.markers = curves[i].points.size() <= 60;
          for (const auto& p : curves[i].points) {
            s.x.push_back(static_cast<double>(p.readings));
            s.y.push_back(panel.get(p));
          }
          // A curve without pose errors (the appearance-only baseline) stays out
          // of the error panels rather than cluttering their legends.
          const bool any = std::any_of(s.y.begin(), s.y.end(), [](double v) { return std::isfinite(v); });
          if (any || panel.percent) series.push_back(std::move(s));
        }
        return series;
      },
      file);
}

void write_reliability_figure(const Curve& curve, const std::filesystem::path& file) {
  const CalibrationSummary& c = curve.calibration;
  if (c.trial_readings == 0) throw Error(file.string() + ": no trial-readings from 2 on to draw a reliability diagram");
  plot::Series ideal, measured;
  ideal.label = "perfectly calibrated";
  ideal.color = plot::kBlack;
  ideal.markers = false;
  ideal.x = {0.0, 1.0};
  ideal.y = {0.0, 1.0};
  measured.label = curve.label + ": accuracy per bin of the top object's probability";
  measured.color = plot::palette(0);
  for (const ReliabilityBin& b : c.bins) {
    if (b.count == 0) continue;
    measured.x.push_back(b.confidence);
    measured.y.push_back(b.accuracy);
  }
  char title[200];
  std::snprintf(title, sizeof title, "%s: reliability (ECE %.3f, confidently wrong %.2f%%, %zu trial-readings)",
                curve.scene.c_str(), c.ece, 100.0 * c.confidently_wrong, c.trial_readings);
  plot::Canvas canvas(720, 620);
  plot::ChartOptions o;
  o.title = title;
  o.x_label = "top object's probability";
  o.y_label = "share right";
  o.x_min = 0.0;
  o.x_max = 1.0;
  o.y_min = 0.0;
  o.y_max = 1.0;
  line_chart(canvas, 0, 0, canvas.width(), canvas.height(), {ideal, measured}, o);
  canvas.write_figure(file);
}

}  // namespace sva::eval
