#pragma once
// The canvas the CLI draws its pictures on (tactile contact sheets, accuracy and error plots, the confusion matrix
// and the reliability diagram): lines, rectangles, filled circles, text, a colormap and a line chart, drawn by
// cairo (antialiased shapes, real fonts), written as PNG and, for figures, as SVG beside it. Coordinates are
// pixels, (0, 0) the top-left corner: a rectangle covers whole pixels, a line of integer ends runs through the
// pixels' centres (as the raster canvas before it drew them), a circle is centred where it is asked.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

typedef struct _cairo cairo_t;
typedef struct _cairo_surface cairo_surface_t;

namespace sva::plot {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

inline constexpr Rgb kWhite{255, 255, 255}, kBlack{0, 0, 0}, kGrey{128, 128, 128}, kLightGrey{220, 220, 220},
    kRed{220, 30, 30};

// A perceptually ordered heat colormap: t in [0, 1] (clamped) from dark blue
// through green to yellow. NaN maps to magenta so that it is never hidden.
Rgb colormap(double t);
// A qualitative palette for series and categories (cycles after 10).
Rgb palette(std::size_t i);

class Canvas {
 public:
  Canvas(int width, int height, Rgb background = kWhite);
  ~Canvas();
  Canvas(Canvas&&) noexcept;
  Canvas& operator=(Canvas&&) noexcept;
  int width() const { return w_; }
  int height() const { return h_; }
  Rgb get(int x, int y) const;    // the rendered pixel (black outside the canvas)
  void set(int x, int y, Rgb c);  // ignores pixels outside the canvas
  void fill_rect(int x, int y, int w, int h, Rgb c);
  void rect(int x, int y, int w, int h, Rgb c);  // outline, one pixel inside the rectangle
  void line(double x0, double y0, double x1, double y1, Rgb c, int thickness = 1);
  void fill_circle(double cx, double cy, double r, Rgb c);
  // Text with its top-left corner at (x, y) in DejaVu Sans (the fonts-dejavu-core package); `scale` multiplies the
  // 10 px size.
  void text(int x, int y, const std::string& s, Rgb c, int scale = 1);
  static int text_width(const std::string& s, int scale = 1);
  static int text_height(int scale = 1) { return 8 * scale; }
  // Writes a PNG through a temporary file and a rename. Throws sva::Error.
  void write_png(const std::filesystem::path& file) const;
  // Writes an SVG (vector shapes, the glyphs as paths), atomically as write_png.
  void write_svg(const std::filesystem::path& file) const;
  // A figure: the PNG `file` and the SVG beside it (the same name, extension .svg).
  void write_figure(const std::filesystem::path& file) const;
  // The rendered pixels, RGB row by row.
  const std::vector<std::uint8_t>& pixels() const;

 private:
  void render() const;  // the drawing so far into px_, when it changed
  int w_, h_;
  cairo_surface_t* record_ = nullptr;  // every drawing operation, replayed into a PNG or an SVG
  cairo_t* cr_ = nullptr;
  mutable std::vector<std::uint8_t> px_;
  mutable bool stale_ = true;
};

struct Series {
  std::string label;
  std::vector<double> x, y;  // equal lengths; non-finite points are skipped
  Rgb color{0, 0, 0};
  bool markers = true;
};

struct ChartOptions {
  std::string title, x_label, y_label;
  std::optional<double> x_min, x_max, y_min, y_max;  // default: the data's range
  int ticks = 5;
};

// Draws a line chart (axes, ticks, labels, series, legend) in the rectangle
// (x, y, w, h) of the canvas.
void line_chart(Canvas& canvas, int x, int y, int w, int h, const std::vector<Series>& series,
                const ChartOptions& options);

}  // namespace sva::plot
