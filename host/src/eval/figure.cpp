#include "eval/figure.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "plot/canvas.hpp"

namespace sva::eval {

namespace {

constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

double value(const std::optional<double>& v) { return v ? *v : kMissing; }

}  // namespace

void write_figure(const std::vector<Curve>& curves, const std::filesystem::path& file) {
  if (curves.empty()) throw Error(file.string() + ": no curves to plot");
  constexpr int kPanelW = 620, kPanelH = 430, kHeader = 34;
  plot::Canvas canvas(2 * kPanelW, 2 * kPanelH + kHeader);

  std::string title = curves.front().scene + ": ";
  for (std::size_t i = 0; i < curves.size(); ++i)
    title += (i ? ", " : "") + curves[i].label + " (" + std::to_string(curves[i].trials) + " trials)";
  canvas.text((canvas.width() - plot::Canvas::text_width(title, 2)) / 2, 10, title, plot::kBlack, 2);

  struct Panel {
    const char* title;
    const char* y_label;
    double (*get)(const CurvePoint&);
    bool percent;
  };
  const Panel panels[] = {
      {"(a) classification accuracy", "accuracy (%)", [](const CurvePoint& p) { return 100.0 * p.accuracy; }, true},
      {"(b) inertial error", "median inertial distance (mm)",
       [](const CurvePoint& p) { return value(p.inertial_mm.median); }, false},
      {"(c) translational error", "median |T_hat - T| (mm)",
       [](const CurvePoint& p) { return value(p.translation_mm.median); }, false},
      {"(d) angular error", "median angle (deg)", [](const CurvePoint& p) { return value(p.angular_deg.median); },
       false},
  };
  double max_readings = 1.0;
  for (const auto& c : curves)
    for (const auto& p : c.points) max_readings = std::max(max_readings, static_cast<double>(p.readings));

  for (int k = 0; k < 4; ++k) {
    std::vector<plot::Series> series;
    for (std::size_t i = 0; i < curves.size(); ++i) {
      plot::Series s;
      s.label = curves[i].label;
      s.color = plot::palette(i);
      s.markers = curves[i].points.size() <= 60;
      for (const auto& p : curves[i].points) {
        s.x.push_back(static_cast<double>(p.readings));
        s.y.push_back(panels[k].get(p));
      }
      // A curve without pose errors (the appearance-only baseline) stays out
      // of the error panels rather than cluttering their legends.
      const bool any = std::any_of(s.y.begin(), s.y.end(), [](double v) { return std::isfinite(v); });
      if (any || panels[k].percent) series.push_back(std::move(s));
    }
    plot::ChartOptions o;
    o.title = panels[k].title;
    o.x_label = "number of readings";
    o.y_label = panels[k].y_label;
    o.x_min = 0.0;
    o.x_max = max_readings;
    o.y_min = 0.0;
    if (panels[k].percent) {
      o.y_max = 100.0;
    } else {
      // Headroom above the largest error so the curve does not run along the frame.
      double top = 0.0;
      for (const auto& s : series)
        for (double v : s.y)
          if (std::isfinite(v)) top = std::max(top, v);
      if (top > 0.0) o.y_max = 1.1 * top;
    }
    line_chart(canvas, (k % 2) * kPanelW, kHeader + (k / 2) * kPanelH, kPanelW, kPanelH, series, o);
  }
  canvas.write_png(file);
}

}  // namespace sva::eval
