// The confusion matrix as a picture (confusion.hpp): each row the share of its object's trials named each map
// object, white for none and darker for more, the diagonal framed, families boxed and named.
#include <sva/error.hpp>
#include <sva/eval/confusion.hpp>

#include <algorithm>
#include <cstdio>

#include "plot/canvas.hpp"

namespace sva::eval {

namespace {

// White for 0, through the heat map's blue for 1: the empty cells of a sparse matrix stay quiet.
plot::Rgb share_color(double share) {
  if (share <= 0.0) return plot::kWhite;
  const plot::Rgb hot = plot::colormap(1.0 - std::min(share, 1.0));
  const double t = 0.25 + 0.75 * std::min(share, 1.0);  // even one trial in ten is clearly visible
  auto mix = [t](std::uint8_t a) { return static_cast<std::uint8_t>(255.0 + t * (a - 255.0)); };
  return {mix(hot.r), mix(hot.g), mix(hot.b)};
}

// [first, last) runs of equal family names.
std::vector<std::pair<std::size_t, std::size_t>> family_runs(const std::vector<std::string>& families) {
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  for (std::size_t i = 0; i < families.size();) {
    std::size_t j = i;
    while (j < families.size() && families[j] == families[i]) ++j;
    runs.push_back({i, j});
    i = j;
  }
  return runs;
}

struct Layout {
  int cell, left, top;
  bool names;  // a label per object (else per family)
};

void draw_cells(plot::Canvas& canvas, const Confusion& c, const Layout& l) {
  for (std::size_t r = 0; r < c.truths.size(); ++r) {
    const std::size_t n = c.trials(r);
    for (std::size_t k = 0; k < c.estimates.size(); ++k) {
      const double share = n ? static_cast<double>(c.counts[r][k]) / static_cast<double>(n) : 0.0;
      canvas.fill_rect(l.left + static_cast<int>(k) * l.cell, l.top + static_cast<int>(r) * l.cell, l.cell, l.cell,
                       share_color(share));
    }
    if (c.truth_column[r] >= 0)
      canvas.rect(l.left + static_cast<int>(c.truth_column[r]) * l.cell, l.top + static_cast<int>(r) * l.cell, l.cell,
                  l.cell, plot::kGrey);
  }
}

void draw_families(plot::Canvas& canvas, const Confusion& c, const Layout& l) {
  const int w = static_cast<int>(c.estimates.size()) * l.cell, h = static_cast<int>(c.truths.size()) * l.cell;
  for (const auto& [a, b] : family_runs(c.truth_families)) {
    const int y0 = l.top + static_cast<int>(a) * l.cell, y1 = l.top + static_cast<int>(b) * l.cell;
    canvas.line(l.left - 4, y0, l.left + w, y0, plot::kBlack);
    if (!l.names) {
      const std::string name = c.truth_families[a].empty() ? "(no family)" : c.truth_families[a];
      canvas.text(l.left - 8 - plot::Canvas::text_width(name), (y0 + y1) / 2 - 4, name, plot::kBlack);
    }
  }
  for (const auto& [a, b] : family_runs(c.estimate_families)) {
    const int x0 = l.left + static_cast<int>(a) * l.cell;
    canvas.line(x0, l.top - 4, x0, l.top + h, plot::kBlack);
  }
  canvas.rect(l.left, l.top, w + 1, h + 1, plot::kBlack);
}

void draw_names(plot::Canvas& canvas, const Confusion& c, const Layout& l) {
  if (!l.names) return;
  for (std::size_t r = 0; r < c.truths.size(); ++r)
    canvas.text(l.left - 8 - plot::Canvas::text_width(c.truths[r]),
                l.top + static_cast<int>(r) * l.cell + (l.cell - 8) / 2, c.truths[r], plot::kBlack);
}

}  // namespace

void write_confusion_figure(const Confusion& c, const std::string& scene, const std::filesystem::path& file) {
  if (c.truths.empty() || c.estimates.empty()) throw Error(file.string() + ": no trials to draw a confusion matrix");
  const int n = static_cast<int>(std::max(c.truths.size(), c.estimates.size()));
  Layout l;
  l.cell = std::clamp(900 / n, 4, 28);
  l.names = l.cell >= 10;
  int label_w = 0;
  for (const std::string& s : l.names ? c.truths : c.truth_families)
    label_w = std::max(label_w, plot::Canvas::text_width(s.empty() ? "(no family)" : s));
  l.left = label_w + 24;
  l.top = 70;
  std::size_t trials = 0, right = 0;
  for (std::size_t r = 0; r < c.truths.size(); ++r) {
    trials += c.trials(r);
    right += c.right(r);
  }
  char title[240];
  std::snprintf(title, sizeof title, "%s: confusion at %zu readings (%zu trials, %.1f%% right)", scene.c_str(),
                c.readings, trials, trials ? 100.0 * right / trials : 0.0);
  const std::string legend =
      "rows: the touched object; columns: the estimate, in the same family order; colour: share of the row's "
      "trials; grey frame: right";
  const int width = std::max({l.left + static_cast<int>(c.estimates.size()) * l.cell + 30,
                              plot::Canvas::text_width(title, 2) + 20, plot::Canvas::text_width(legend) + 20});
  plot::Canvas canvas(width, l.top + static_cast<int>(c.truths.size()) * l.cell + 40);
  canvas.text(10, 10, title, plot::kBlack, 2);
  canvas.text(10, 36, legend, plot::kGrey);
  draw_cells(canvas, c, l);
  draw_families(canvas, c, l);
  draw_names(canvas, c, l);
  canvas.write_figure(file);
}

}  // namespace sva::eval
