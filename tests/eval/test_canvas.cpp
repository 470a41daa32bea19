// The raster canvas used for previews and plots.
#include <catch2/catch.hpp>

#include <fstream>

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
  int before = 0, after = 0;
  for (int y = 40; y < 60; ++y)
    for (int x = 40; x < 120; ++x) before += c.get(x, y) == kBlack;
  c.text(40, 45, "Hello 42", kBlack);
  for (int y = 40; y < 60; ++y)
    for (int x = 40; x < 120; ++x) after += c.get(x, y) == kBlack;
  CHECK(after > before + 20);
  CHECK(Canvas::text_width("Hello 42") > Canvas::text_width("Hi"));
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
  chart.write_png(dir / "chart.png");
  std::ifstream in(dir / "chart.png", std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  CHECK(std::string(magic + 1, 3) == "PNG");
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) files += 1 + (e.path().filename() != "chart.png");
  CHECK(files == 1);  // no temporary file left beside it
}
