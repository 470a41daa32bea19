// The contact sheet of `sva simulate --preview`: per reading, the pressure
// image as a heat map beside an oblique view of all contact points of that
// object, with this reading's point and normal highlighted.
#include <sva/error.hpp>
#include <sva/eval/dataset_export.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "plot/canvas.hpp"

namespace sva::io {

namespace {

const char* status_word(ControllerStatus s) {
  switch (s) {
    case ControllerStatus::converged:
      return "ok";
    case ControllerStatus::not_converged:
      return "NOT CONV";
    case ControllerStatus::no_contact:
      return "NO CONTACT";
  }
  return "?";
}

// A fixed oblique view (azimuth 35 degrees, elevation 25 degrees, z up) for
// 3D scenes; straight down for planar ones.
glm::dvec2 project(const glm::dvec3& p, bool top_down) {
  if (top_down) return {p.x, p.y};
  const double az = 35.0 * M_PI / 180.0, el = 25.0 * M_PI / 180.0;
  double x = std::cos(az) * p.x + std::sin(az) * p.y;
  double d = -std::sin(az) * p.x + std::cos(az) * p.y;
  double y = std::cos(el) * p.z - std::sin(el) * d;
  return {x, y};
}

constexpr int kCell = 84;  // side of a heat map and of a contact view, pixels

// The colour scale's top: the 99th percentile of the non-zero pressures, so that a few saturated elements do not
// wash out every other image.
float pressure_scale(const Dataset& data) {
  std::vector<float> all;
  for (const auto& s : data.samples)
    for (float p : s.reading.pressure)
      if (p > 0) all.push_back(p);
  if (all.empty()) return 1.0f;
  auto k = all.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(all.size() - 1));
  std::nth_element(all.begin(), k, all.end());
  return std::max(*k, 1e-3f);
}

using Bounds = std::map<std::uint32_t, std::pair<glm::dvec2, glm::dvec2>>;

// Per object: the projected bounds of its contact points.
Bounds contact_bounds(const Dataset& data, bool top_down) {
  Bounds bounds;
  for (const auto& s : data.samples) {
    if (s.reading.status == ControllerStatus::no_contact) continue;
    glm::dvec2 q = project(s.reading.position, top_down);
    auto [it, fresh] = bounds.try_emplace(s.object, q, q);
    if (!fresh) it->second = {glm::min(it->second.first, q), glm::max(it->second.second, q)};
  }
  return bounds;
}

// The pressure image at (ox, oy): row 0 (most negative sensor y) at the bottom, like a plot.
void draw_heat_map(plot::Canvas& cv, const Reading& r, const SensorSpec& sensor, float pmax, int ox, int oy) {
  const int rs = sensor.rows, cs = sensor.cols;
  const int ew = std::max(1, kCell / std::max(rs, cs));
  for (int i = 0; i < rs; ++i)
    for (int j = 0; j < cs; ++j) {
      float p = r.pressure.size() == static_cast<std::size_t>(rs * cs)
                    ? r.pressure[static_cast<std::size_t>(i * cs + j)]
                    : 0.0f;
      cv.fill_rect(ox + j * ew, oy + (rs - 1 - i) * ew, ew, ew, plot::colormap(p / pmax));
    }
  cv.rect(ox - 1, oy - 1, cs * ew + 2, rs * ew + 2, plot::kGrey);
}

// All contact points of `object` at (vx, oy), with this reading's point and normal in red.
void draw_contact_view(plot::Canvas& cv, const Dataset& data, const Bounds& bounds, bool top_down, std::uint32_t object,
                       const Reading& r, int vx, int oy) {
  cv.rect(vx, oy, kCell, kCell, plot::kLightGrey);
  auto b = bounds.find(object);
  if (b == bounds.end()) return;
  const glm::dvec2 lo = b->second.first, hi = b->second.second;
  const double span = std::max({hi.x - lo.x, hi.y - lo.y, 1e-6});
  auto to_px = [&](const glm::dvec3& p) {
    glm::dvec2 q = (project(p, top_down) - 0.5 * (lo + hi)) / span;
    return glm::dvec2(vx + kCell / 2.0 + q.x * (kCell - 8), oy + kCell / 2.0 - q.y * (kCell - 8));
  };
  for (const auto& s : data.samples) {
    if (s.object != object || s.reading.status == ControllerStatus::no_contact) continue;
    glm::dvec2 q = to_px(s.reading.position);
    cv.set(static_cast<int>(q.x), static_cast<int>(q.y), plot::kGrey);
  }
  if (r.status != ControllerStatus::no_contact) {
    glm::dvec2 q = to_px(r.position), e = to_px(r.position + 0.25 * span * r.normal);
    cv.line(q.x, q.y, e.x, e.y, plot::kRed, 1);
    cv.fill_circle(q.x, q.y, 3.0, plot::kRed);
  }
}

}  // namespace

void write_preview(const Dataset& data, const std::filesystem::path& png, int max_readings) {
  if (max_readings < 1) throw Error("preview: max_readings must be at least 1");
  const std::size_t n = data.samples.size();
  const int shown = static_cast<int>(std::min<std::size_t>(n, static_cast<std::size_t>(max_readings)));
  const bool top_down = data.scene.pose_space.kind == PoseSpaceSpec::Kind::planar;
  const int cell_w = 2 * kCell + 14, cell_h = kCell + 30, cols = std::max(1, std::min(shown, 6));
  const int rows = std::max(1, (shown + cols - 1) / cols);
  const int header = 34;
  plot::Canvas cv(cols * cell_w + 10, header + rows * cell_h + 24);
  const float pmax = pressure_scale(data);
  char title[256];
  std::snprintf(title, sizeof title, "%s / %s: %zu readings (%zu converged), showing %d", data.scene.name.c_str(),
                data.split.c_str(), n, data.count_converged(), shown);
  cv.text(6, 6, title, plot::kBlack, 2);

  const Bounds bounds = contact_bounds(data, top_down);
  for (int c = 0; c < shown; ++c) {
    // Evenly spaced over the dataset so that every object appears.
    std::size_t idx = shown > 1 ? static_cast<std::size_t>(c) * (n - 1) / static_cast<std::size_t>(shown - 1) : 0;
    const Reading& r = data.samples[idx].reading;
    const std::uint32_t object = data.samples[idx].object;
    const int ox = 6 + (c % cols) * cell_w, oy = header + (c / cols) * cell_h;
    draw_heat_map(cv, r, data.scene.sensor, pmax, ox, oy);
    draw_contact_view(cv, data, bounds, top_down, object, r, ox + kCell + 8, oy);
    std::string name = object < data.scene.objects.size() ? data.scene.objects[object].name : "?";
    char cap[160];
    std::snprintf(cap, sizeof cap, "#%zu %s", idx, name.c_str());
    cv.text(ox, oy + kCell + 4, cap, plot::kBlack);
    std::snprintf(cap, sizeof cap, "%s, %d it", status_word(r.status), static_cast<int>(r.iterations));
    cv.text(ox, oy + kCell + 15, cap, r.status == ControllerStatus::converged ? plot::kGrey : plot::kRed);
  }
  // Colour scale.
  int ly = header + rows * cell_h + 4;
  for (int k = 0; k < 200; ++k) cv.fill_rect(6 + k, ly, 1, 10, plot::colormap(k / 199.0));
  char scale[64];
  std::snprintf(scale, sizeof scale, "0 .. %.1f kPa (99th percentile)", static_cast<double>(pmax));
  cv.text(212, ly + 1, scale, plot::kBlack);
  cv.write_png(png);
}

}  // namespace sva::io
