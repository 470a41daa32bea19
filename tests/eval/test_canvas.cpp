// The canvas of previews and figures (cairo): exact cells, lines through pixel centres, real glyphs, PNG and SVG.
#include <catch2/catch.hpp>

#include <fstream>
#include <iterator>
#include <set>

#include "plot/canvas.hpp"
#include "test_support.hpp"

using namespace sva::plot;

TEST_CASE("canvas: shapes, text, colormap, chart and PNG") {
  Canvas c(200, 120);
  CHECK(c.get(10, 10) == kWhite);
  c.fill_rect(10, 10, 5, 5, kRed);
  CHECK(c.get(12, 12) == kRed);
  CHECK(c.get(15, 15) == kWhite);
  c.line(0, 100, 199, 100, kBlack);
  CHECK(c.get(100, 100) == kBlack);
  c.fill_circle(150, 30, 6, kGrey);
  CHECK(c.get(150, 30) == kGrey);
  CHECK(c.get(150, 40) == kWhite);
  c.set(-1, 5000, kRed);  // outside: ignored
  // Antialiased glyphs: count the dark pixels (a font found, glyphs drawn where asked, about 7 px tall).
  const auto dark = [&](const Canvas& cv, int x0, int y0, int x1, int y1) {
    int n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) n += cv.get(x, y).r < 128;
    return n;
  };
  const int before = dark(c, 40, 40, 120, 60);
  c.text(40, 45, "Hello 42", kBlack);
  CHECK(dark(c, 40, 40, 120, 60) > before + 40);
  CHECK(dark(c, 40, 40, 120, 44) == 0);  // nothing above the capitals' top
  CHECK(Canvas::text_width("Hello 42") > Canvas::text_width("Hi"));
  CHECK(Canvas::text_width("Hello 42") >= 30);
  CHECK(Canvas::text_width("Hello 42") <= 60);
  CHECK(Canvas::text_width("Hello 42", 2) >= 2 * Canvas::text_width("Hello 42") - 2);
  CHECK(colormap(0.0) != colormap(1.0));
  CHECK(colormap(-5) == colormap(0.0));
  CHECK(colormap(std::nan("")) == Rgb{255, 0, 255});

  Canvas chart(400, 300);
  line_chart(
      chart, 0, 0, 400, 300,
      {{"accuracy", {1, 2, 3, 4}, {0.2, 0.5, 0.8, 1.0}, palette(0)}, {"baseline", {1, 4}, {0.1, 0.3}, palette(1)}},
      {"Accuracy", "readings", "fraction"});
  int coloured = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 400; ++x) coloured += chart.get(x, y) == palette(0);
  CHECK(coloured > 50);

  auto dir = sva::test::temp_dir("canvas");
  chart.write_figure(dir / "chart.png");
  std::ifstream in(dir / "chart.png", std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  CHECK(std::string(magic + 1, 3) == "PNG");
  std::ifstream svg(dir / "chart.svg");
  const std::string text((std::istreambuf_iterator<char>(svg)), std::istreambuf_iterator<char>());
  CHECK(text.find("<svg") != std::string::npos);
  CHECK(text.find("width=\"400") != std::string::npos);
  CHECK(text.find("</svg>") != std::string::npos);
  std::set<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) names.insert(e.path().filename().string());
  CHECK(names == std::set<std::string>{"chart.png", "chart.svg"});  // no temporary file left beside them
  // Moved canvases keep their drawing.
  Canvas moved = std::move(chart);
  CHECK(moved.get(0, 0) == kWhite);
}
