#include "plot/canvas.hpp"

#include <sva/error.hpp>
#include <sva/io/text_file.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>

#include <cairo-svg.h>
#include <cairo.h>

#include <cstring>
#include <string>
#include <utility>

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
  const cairo_rectangle_t extents{0, 0, static_cast<double>(w_), static_cast<double>(h_)};
  record_ = cairo_recording_surface_create(CAIRO_CONTENT_COLOR, &extents);
  cr_ = cairo_create(record_);
  if (cairo_status(cr_) != CAIRO_STATUS_SUCCESS)
    throw Error("canvas " + std::to_string(w_) + " x " + std::to_string(h_) + ": " +
                cairo_status_to_string(cairo_status(cr_)));
  fill_rect(0, 0, w_, h_, bg);
}

Canvas::~Canvas() {
  if (cr_) cairo_destroy(cr_);
  if (record_) cairo_surface_destroy(record_);
}

Canvas::Canvas(Canvas&& o) noexcept
    : w_(o.w_),
      h_(o.h_),
      record_(std::exchange(o.record_, nullptr)),
      cr_(std::exchange(o.cr_, nullptr)),
      px_(std::move(o.px_)),
      stale_(o.stale_) {}

Canvas& Canvas::operator=(Canvas&& o) noexcept {
  if (this != &o) {
    this->~Canvas();
    new (this) Canvas(std::move(o));
  }
  return *this;
}

namespace {
void source(cairo_t* cr, Rgb c) { cairo_set_source_rgb(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0); }

// The sizes of text as Canvas::text draws it: a context of its own per thread (figures are drawn in parallel).
cairo_t* measuring_context() {
  thread_local std::unique_ptr<cairo_t, void (*)(cairo_t*)> cr = [] {
    cairo_surface_t* s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1);
    cairo_t* c = cairo_create(s);
    cairo_surface_destroy(s);  // the context holds it
    return std::unique_ptr<cairo_t, void (*)(cairo_t*)>(c, cairo_destroy);
  }();
  return cr.get();
}

void select_font(cairo_t* cr, int scale) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 10.0 * std::max(scale, 1));
}

// Appends what cairo writes to a byte string (PNG and SVG streams).
cairo_status_t append(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

// A finite coordinate, clamped far outside the canvas (cairo's fixed point overflows past 2^23).
double bounded(double v, double lim) { return std::clamp(v, -lim, lim); }
}  // namespace

void Canvas::render() const {
  if (!stale_) return;
  cairo_surface_t* image = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w_, h_);
  cairo_t* cr = cairo_create(image);
  cairo_set_source_surface(cr, record_, 0, 0);
  cairo_paint(cr);
  cairo_destroy(cr);
  cairo_surface_flush(image);
  const unsigned char* data = cairo_image_surface_get_data(image);
  const int stride = cairo_image_surface_get_stride(image);
  px_.resize(static_cast<std::size_t>(w_) * h_ * 3);
  for (int y = 0; y < h_; ++y)
    for (int x = 0; x < w_; ++x) {
      std::uint32_t v;  // RGB24: 0x00RRGGBB in the machine's byte order
      std::memcpy(&v, data + static_cast<std::size_t>(y) * stride + 4 * x, 4);
      std::uint8_t* p = px_.data() + (static_cast<std::size_t>(y) * w_ + x) * 3;
      p[0] = static_cast<std::uint8_t>(v >> 16), p[1] = static_cast<std::uint8_t>(v >> 8);
      p[2] = static_cast<std::uint8_t>(v);
    }
  cairo_surface_destroy(image);
  stale_ = false;
}

const std::vector<std::uint8_t>& Canvas::pixels() const {
  render();
  return px_;
}

Rgb Canvas::get(int x, int y) const {
  if (x < 0 || y < 0 || x >= w_ || y >= h_) return {};
  render();
  std::size_t i = (static_cast<std::size_t>(y) * w_ + x) * 3;
  return {px_[i], px_[i + 1], px_[i + 2]};
}

void Canvas::set(int x, int y, Rgb c) {
  if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
  fill_rect(x, y, 1, 1, c);
}

void Canvas::fill_rect(int x, int y, int w, int h, Rgb c) {
  const int x0 = std::max(x, 0), y0 = std::max(y, 0), x1 = std::min(x + w, w_), y1 = std::min(y + h, h_);
  if (x1 <= x0 || y1 <= y0) return;
  // Whole pixels, without antialiasing: the cells of heat maps and contact sheets keep their exact colours.
  cairo_set_antialias(cr_, CAIRO_ANTIALIAS_NONE);
  source(cr_, c);
  cairo_rectangle(cr_, x0, y0, x1 - x0, y1 - y0);
  cairo_fill(cr_);
  cairo_set_antialias(cr_, CAIRO_ANTIALIAS_DEFAULT);
  stale_ = true;
}

void Canvas::rect(int x, int y, int w, int h, Rgb c) {
  fill_rect(x, y, w, 1, c);
  fill_rect(x, y + h - 1, w, 1, c);
  fill_rect(x, y, 1, h, c);
  fill_rect(x + w - 1, y, 1, h, c);
}

void Canvas::line(double x0, double y0, double x1, double y1, Rgb c, int thickness) {
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) return;
  const double lim = 4.0 * (w_ + h_);
  // Through the pixels' centres: a line from (x, y) covers pixel (x, y).
  cairo_move_to(cr_, bounded(x0, lim) + 0.5, bounded(y0, lim) + 0.5);
  cairo_line_to(cr_, bounded(x1, lim) + 0.5, bounded(y1, lim) + 0.5);
  cairo_set_line_width(cr_, std::max(thickness, 1));
  cairo_set_line_cap(cr_, CAIRO_LINE_CAP_SQUARE);
  source(cr_, c);
  cairo_stroke(cr_);
  stale_ = true;
}

void Canvas::fill_circle(double cx, double cy, double r, Rgb c) {
  if (!std::isfinite(cx) || !std::isfinite(cy) || !(r > 0) || !std::isfinite(r)) return;
  const double lim = 4.0 * (w_ + h_);
  cairo_arc(cr_, bounded(cx, lim), bounded(cy, lim), std::min(r, lim), 0.0, 2.0 * M_PI);
  source(cr_, c);
  cairo_fill(cr_);
  stale_ = true;
}

void Canvas::text(int x, int y, const std::string& s, Rgb c, int scale) {
  if (s.empty()) return;
  select_font(cr_, scale);
  cairo_font_extents_t fe;
  cairo_font_extents(cr_, &fe);
  // The 10 px font's capitals are about 7 px tall, as the text heights the figures are laid out for: the top of
  // the capitals at y.
  cairo_text_extents_t te;
  cairo_text_extents(cr_, "H", &te);
  source(cr_, c);
  cairo_move_to(cr_, x, y - te.y_bearing);
  cairo_show_text(cr_, s.c_str());
  cairo_new_path(cr_);
  stale_ = true;
}

int Canvas::text_width(const std::string& s, int scale) {
  if (s.empty()) return 0;
  cairo_t* cr = measuring_context();
  select_font(cr, scale);
  cairo_text_extents_t te;
  cairo_text_extents(cr, s.c_str(), &te);
  return static_cast<int>(std::ceil(te.x_advance));
}

void Canvas::write_png(const std::filesystem::path& file) const {
  cairo_surface_t* image = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w_, h_);
  cairo_t* cr = cairo_create(image);
  cairo_set_source_surface(cr, record_, 0, 0);
  cairo_paint(cr);
  cairo_destroy(cr);
  std::string bytes;
  const cairo_status_t st = cairo_surface_write_to_png_stream(image, append, &bytes);
  cairo_surface_destroy(image);
  if (st != CAIRO_STATUS_SUCCESS) throw Error(file.string() + ": cannot encode PNG: " + cairo_status_to_string(st));
  io::write_file_atomically(
      file, [&](std::ostream& out) { out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
}

void Canvas::write_svg(const std::filesystem::path& file) const {
  std::string bytes;
  cairo_surface_t* svg = cairo_svg_surface_create_for_stream(append, &bytes, w_, h_);
  cairo_t* cr = cairo_create(svg);
  cairo_set_source_surface(cr, record_, 0, 0);
  cairo_paint(cr);
  cairo_destroy(cr);
  cairo_surface_finish(svg);
  const cairo_status_t st = cairo_surface_status(svg);
  cairo_surface_destroy(svg);
  if (st != CAIRO_STATUS_SUCCESS) throw Error(file.string() + ": cannot encode SVG: " + cairo_status_to_string(st));
  io::write_file_atomically(
      file, [&](std::ostream& out) { out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
}

void Canvas::write_figure(const std::filesystem::path& file) const {
  write_png(file);
  write_svg(std::filesystem::path(file).replace_extension(".svg"));
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
