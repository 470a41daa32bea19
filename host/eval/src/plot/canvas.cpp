#include "plot/canvas.hpp"

#include <sva/error.hpp>
#include <sva/io/text_file.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_easy_font.h>
#include <stb_image_write.h>

namespace sva::plot {

Rgb colormap(double t) {
  if (std::isnan(t)) return {255, 0, 255};
  t = std::clamp(t, 0.0, 1.0);
  // Piecewise-linear through hand-picked stops (dark blue, blue, teal, green, yellow).
  static const double stops[][3] = {{20, 20, 60}, {40, 70, 170}, {30, 150, 150}, {90, 200, 80}, {250, 230, 40}};
  const int n = 4;
  double f = t * n;
  int i = std::min(static_cast<int>(f), n - 1);
  double u = f - i;
  auto mix = [&](int k) {
    return static_cast<std::uint8_t>(std::lround(stops[i][k] + u * (stops[i + 1][k] - stops[i][k])));
  };
  return {mix(0), mix(1), mix(2)};
}

Rgb palette(std::size_t i) {
  static const Rgb p[] = {{31, 119, 180}, {255, 127, 14},  {44, 160, 44},   {214, 39, 40},  {148, 103, 189},
                          {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};
  return p[i % 10];
}

Canvas::Canvas(int width, int height, Rgb bg) : w_(std::max(width, 1)), h_(std::max(height, 1)) {
  px_.resize(static_cast<std::size_t>(w_) * h_ * 3);
  for (std::size_t i = 0; i < px_.size(); i += 3) {
    px_[i] = bg.r;
    px_[i + 1] = bg.g;
    px_[i + 2] = bg.b;
  }
}

Rgb Canvas::get(int x, int y) const {
  if (x < 0 || y < 0 || x >= w_ || y >= h_) return {};
  std::size_t i = (static_cast<std::size_t>(y) * w_ + x) * 3;
  return {px_[i], px_[i + 1], px_[i + 2]};
}

void Canvas::set(int x, int y, Rgb c) {
  if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
  std::size_t i = (static_cast<std::size_t>(y) * w_ + x) * 3;
  px_[i] = c.r;
  px_[i + 1] = c.g;
  px_[i + 2] = c.b;
}

void Canvas::fill_rect(int x, int y, int w, int h, Rgb c) {
  int x0 = std::max(x, 0), y0 = std::max(y, 0), x1 = std::min(x + w, w_), y1 = std::min(y + h, h_);
  for (int yy = y0; yy < y1; ++yy)
    for (int xx = x0; xx < x1; ++xx) set(xx, yy, c);
}

void Canvas::rect(int x, int y, int w, int h, Rgb c) {
  fill_rect(x, y, w, 1, c);
  fill_rect(x, y + h - 1, w, 1, c);
  fill_rect(x, y, 1, h, c);
  fill_rect(x + w - 1, y, 1, h, c);
}

void Canvas::line(double x0, double y0, double x1, double y1, Rgb c, int thickness) {
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) return;
  // Clip absurdly long lines so that the loop stays bounded.
  const double lim = 4.0 * (w_ + h_);
  x0 = std::clamp(x0, -lim, lim), x1 = std::clamp(x1, -lim, lim), y0 = std::clamp(y0, -lim, lim),
  y1 = std::clamp(y1, -lim, lim);
  double len = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
  int steps = std::max(1, static_cast<int>(std::ceil(len)));
  int r = std::max(thickness, 1) / 2;
  int extra = std::max(thickness, 1) - 1 - 2 * r;
  for (int i = 0; i <= steps; ++i) {
    double t = static_cast<double>(i) / steps;
    int x = static_cast<int>(std::lround(x0 + t * (x1 - x0))), y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
    for (int dy = -r; dy <= r + extra; ++dy)
      for (int dx = -r; dx <= r + extra; ++dx) set(x + dx, y + dy, c);
  }
}

void Canvas::fill_circle(double cx, double cy, double r, Rgb c) {
  if (!std::isfinite(cx) || !std::isfinite(cy) || !(r > 0)) return;
  int x0 = static_cast<int>(std::floor(cx - r)), x1 = static_cast<int>(std::ceil(cx + r));
  int y0 = static_cast<int>(std::floor(cy - r)), y1 = static_cast<int>(std::ceil(cy + r));
  x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, w_ - 1), y1 = std::min(y1, h_ - 1);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      if ((x + 0.5 - cx) * (x + 0.5 - cx) + (y + 0.5 - cy) * (y + 0.5 - cy) <= r * r) set(x, y, c);
}

void Canvas::text(int x, int y, const std::string& s, Rgb c, int scale) {
  if (s.empty()) return;
  scale = std::max(scale, 1);
  std::string copy = s;
  // stb_easy_font emits axis-aligned quads (4 vertices of 16 bytes each).
  std::vector<char> buf(copy.size() * 300 + 1024);
  unsigned char col[4] = {c.r, c.g, c.b, 255};
  int quads = stb_easy_font_print(0, 0, copy.data(), col, buf.data(), static_cast<int>(buf.size()));
  for (int q = 0; q < quads; ++q) {
    const float* v = reinterpret_cast<const float*>(buf.data() + q * 64);
    float qx0 = v[0], qy0 = v[1], qx1 = v[8], qy1 = v[9];  // vertices 0 and 2 are opposite corners
    int ax = x + static_cast<int>(std::lround(std::min(qx0, qx1) * scale));
    int ay = y + static_cast<int>(std::lround(std::min(qy0, qy1) * scale));
    int bw = static_cast<int>(std::lround(std::abs(qx1 - qx0) * scale));
    int bh = static_cast<int>(std::lround(std::abs(qy1 - qy0) * scale));
    fill_rect(ax, ay, std::max(bw, 1), std::max(bh, 1), c);
  }
}

int Canvas::text_width(const std::string& s, int scale) {
  std::string copy = s;
  return stb_easy_font_width(copy.data()) * std::max(scale, 1);
}

void Canvas::write_png(const std::filesystem::path& file) const {
  io::write_file_atomically(file, [&](std::ostream& out) {
    const auto to_stream = [](void* context, void* data, int size) {
      static_cast<std::ostream*>(context)->write(static_cast<const char*>(data), size);
    };
    if (!stbi_write_png_to_func(to_stream, &out, w_, h_, 3, px_.data(), w_ * 3))
      throw Error(file.string() + ": cannot encode PNG");
  });
}

namespace {
std::string tick_label(double v, double step) {
  char b[32];
  int decimals = step >= 1 ? 0 : std::min(6, static_cast<int>(std::ceil(-std::log10(step))));
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}
// A "nice" tick step (1, 2 or 5 times a power of ten) for about n ticks.
double nice_step(double range, int n) {
  double raw = range / std::max(n, 1);
  double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

// The data range a chart shows, and where it lies on the canvas.
struct ChartFrame {
  double xmin = 0, xmax = 1, ymin = 0, ymax = 1;
  int left = 0, right = 0, top = 0, bottom = 0;
  double px(double v) const { return left + (v - xmin) / (xmax - xmin) * (right - left); }
  double py(double v) const { return bottom - (v - ymin) / (ymax - ymin) * (bottom - top); }
};

// The finite points' range, overridden by the options' fixed bounds; never empty.
void fit_range(const std::vector<Series>& series, const ChartOptions& o, ChartFrame& f) {
  double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin, ymin = xmin, ymax = -xmin;
  for (const auto& s : series)
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
        xmin = std::min(xmin, s.x[i]), xmax = std::max(xmax, s.x[i]);
        ymin = std::min(ymin, s.y[i]), ymax = std::max(ymax, s.y[i]);
      }
  if (!std::isfinite(xmin)) xmin = 0, xmax = 1, ymin = 0, ymax = 1;
  f.xmin = o.x_min.value_or(xmin), f.xmax = o.x_max.value_or(xmax);
  f.ymin = o.y_min.value_or(ymin), f.ymax = o.y_max.value_or(ymax);
  if (!(f.xmax > f.xmin)) f.xmax = f.xmin + 1;
  if (!(f.ymax > f.ymin)) f.ymax = f.ymin + 1;
}

// Grid lines, ticks with labels, the axes and their labels.
void draw_axes(Canvas& cv, int x, int y, const ChartFrame& f, const ChartOptions& o) {
  const double xs = nice_step(f.xmax - f.xmin, o.ticks), ys = nice_step(f.ymax - f.ymin, o.ticks);
  for (double v = std::ceil(f.xmin / xs) * xs; v <= f.xmax + 1e-9 * xs; v += xs) {
    int X = static_cast<int>(std::lround(f.px(v)));
    cv.line(X, f.top, X, f.bottom, kLightGrey);
    cv.line(X, f.bottom, X, f.bottom + 4, kBlack);
    std::string l = tick_label(v, xs);
    cv.text(X - Canvas::text_width(l) / 2, f.bottom + 7, l, kBlack);
  }
  for (double v = std::ceil(f.ymin / ys) * ys; v <= f.ymax + 1e-9 * ys; v += ys) {
    int Y = static_cast<int>(std::lround(f.py(v)));
    cv.line(f.left, Y, f.right, Y, kLightGrey);
    cv.line(f.left - 4, Y, f.left, Y, kBlack);
    std::string l = tick_label(v, ys);
    cv.text(f.left - 7 - Canvas::text_width(l), Y - 4, l, kBlack);
  }
  cv.line(f.left, f.bottom, f.right, f.bottom, kBlack);
  cv.line(f.left, f.top, f.left, f.bottom, kBlack);
  if (!o.x_label.empty())
    cv.text((f.left + f.right - Canvas::text_width(o.x_label)) / 2, f.bottom + 22, o.x_label, kBlack);
  if (!o.y_label.empty()) cv.text(x + 2, f.top - 12 < y ? y : f.top - 12, o.y_label, kBlack);
}

// Each series as a polyline (broken at non-finite points), clamped to the frame.
void draw_series(Canvas& cv, const ChartFrame& f, const std::vector<Series>& series) {
  for (const auto& s : series) {
    bool have = false;
    double lx = 0, ly = 0;
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
        have = false;
        continue;
      }
      double X = f.px(std::clamp(s.x[i], f.xmin, f.xmax)), Y = f.py(std::clamp(s.y[i], f.ymin, f.ymax));
      if (have) cv.line(lx, ly, X, Y, s.color, 2);
      if (s.markers) cv.fill_circle(X, Y, 2.5, s.color);
      lx = X, ly = Y, have = true;
    }
  }
}

// The labelled series' legend, top right inside the plot area.
void draw_legend(Canvas& cv, const ChartFrame& f, const std::vector<Series>& series) {
  int lw = 0, rows = 0;
  for (const auto& s : series) lw = std::max(lw, Canvas::text_width(s.label)), rows += !s.label.empty();
  if (!rows) return;
  const int lx = f.right - lw - 34;
  int ly = f.top + 6;
  cv.fill_rect(lx - 4, ly - 4, lw + 36, rows * 12 + 6, kWhite);
  cv.rect(lx - 4, ly - 4, lw + 36, rows * 12 + 6, kGrey);
  for (const auto& s : series) {
    if (s.label.empty()) continue;
    cv.line(lx, ly + 4, lx + 20, ly + 4, s.color, 2);
    cv.text(lx + 26, ly, s.label, kBlack);
    ly += 12;
  }
}

}  // namespace

void line_chart(Canvas& cv, int x, int y, int w, int h, const std::vector<Series>& series, const ChartOptions& o) {
  ChartFrame f;
  fit_range(series, o, f);
  f.left = x + 56, f.right = x + w - 12, f.top = y + (o.title.empty() ? 10 : 28), f.bottom = y + h - 40;
  if (f.right - f.left < 20 || f.bottom - f.top < 20) return;
  if (!o.title.empty()) cv.text(x + (w - Canvas::text_width(o.title, 2)) / 2, y + 4, o.title, kBlack, 2);
  draw_axes(cv, x, y, f, o);
  draw_series(cv, f, series);
  draw_legend(cv, f, series);
}

}  // namespace sva::plot
