#pragma once
// A small RGB raster canvas for pictures the CLI writes (tactile contact
// sheets, accuracy and error plots): lines, rectangles, filled circles, text
// (stb_easy_font glyphs), a colormap, a line chart, and atomic PNG output.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

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
  int width() const { return w_; }
  int height() const { return h_; }
  Rgb get(int x, int y) const;
  void set(int x, int y, Rgb c);  // ignores pixels outside the canvas
  void fill_rect(int x, int y, int w, int h, Rgb c);
  void rect(int x, int y, int w, int h, Rgb c);  // outline
  void line(double x0, double y0, double x1, double y1, Rgb c, int thickness = 1);
  void fill_circle(double cx, double cy, double r, Rgb c);
  // Text with its top-left corner at (x, y); `scale` multiplies the ~7 px glyphs.
  void text(int x, int y, const std::string& s, Rgb c, int scale = 1);
  static int text_width(const std::string& s, int scale = 1);
  static int text_height(int scale = 1) { return 8 * scale; }
  // Writes a PNG through a temporary file and a rename. Throws sva::Error.
  void write_png(const std::filesystem::path& file) const;
  const std::vector<std::uint8_t>& pixels() const { return px_; }

 private:
  int w_, h_;
  std::vector<std::uint8_t> px_;
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
