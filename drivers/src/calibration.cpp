#include <sva/drivers/calibration.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/text_file.hpp"

namespace sva::drivers {

namespace {
void check_size(const TactileFrame& f, const SensorSpec& s) {
  if (f.rows != s.rows || f.cols != s.cols ||
      f.counts.size() != static_cast<std::size_t>(s.rows) * static_cast<std::size_t>(s.cols))
    throw Error("tactile frame is " + std::to_string(f.rows) + " x " + std::to_string(f.cols) +
                ", the calibration is for " + std::to_string(s.rows) + " x " + std::to_string(s.cols));
}

void validate(const Calibration& c, const std::string& source) {
  auto fail = [&](const std::string& what) { return Error(source + ": " + what); };
  if (c.sensor.rows < 1 || c.sensor.cols < 1 || c.sensor.rows > 255 || c.sensor.cols > 255)
    throw fail("rows/cols must be in [1, 255]");
  if (!(c.sensor.pitch_mm > 0) || !std::isfinite(c.sensor.pitch_mm)) throw fail("pitch_mm must be positive");
  const auto n = static_cast<std::size_t>(c.sensor.elements());
  if (c.gain.size() != n || c.zero.size() != n)
    throw fail("gain_kpa_per_count and zero_counts need rows*cols values each");
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(c.gain[i]) || !std::isfinite(c.zero[i]) || c.gain[i] < 0)
      throw fail("non-finite or negative calibration value at element " + std::to_string(i));
  if (c.saturation_counts == 0) throw fail("saturation_counts must be positive");
}
}  // namespace

Calibration Calibration::uniform(const SensorSpec& sensor, float gain, float zero) {
  Calibration c;
  c.sensor = sensor;
  c.gain.assign(static_cast<std::size_t>(sensor.elements()), gain);
  c.zero.assign(static_cast<std::size_t>(sensor.elements()), zero);
  return c;
}

Calibration Calibration::from_json(const std::string& text, const std::string& source) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(source + ": invalid JSON: " + e.what());
  }
  if (!j.is_object()) throw Error(source + ": expected a JSON object");
  Calibration c;
  try {
    c.sensor.rows = j.at("rows").get<int>();
    c.sensor.cols = j.at("cols").get<int>();
    c.sensor.pitch_mm = j.at("pitch_mm").get<double>();
    c.gain = j.at("gain_kpa_per_count").get<std::vector<float>>();
    c.zero = j.at("zero_counts").get<std::vector<float>>();
    const int saturation = j.value("saturation_counts", 65535);
    if (saturation < 1 || saturation > 65535) throw Error(source + ": saturation_counts must be in [1, 65535]");
    c.saturation_counts = static_cast<std::uint16_t>(saturation);
  } catch (const nlohmann::json::exception& e) {
    throw Error(source + ": missing or mistyped field: " + e.what());
  }
  validate(c, source);
  return c;
}

Calibration Calibration::load(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw Error(file.string() + ": cannot read calibration file");
  std::stringstream text;
  text << in.rdbuf();
  return from_json(text.str(), file.string());
}

std::string Calibration::to_json() const {
  nlohmann::json j{{"rows", sensor.rows},        {"cols", sensor.cols}, {"pitch_mm", sensor.pitch_mm},
                   {"gain_kpa_per_count", gain}, {"zero_counts", zero}, {"saturation_counts", saturation_counts}};
  return j.dump();
}

void Calibration::save(const std::filesystem::path& file) const { io::write_text_file(file, to_json() + "\n"); }

std::vector<float> Calibration::to_pressure(const TactileFrame& f) const {
  check_size(f, sensor);
  std::vector<float> p(f.counts.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    p[i] = std::max(0.0f, gain[i] * (static_cast<float>(f.counts[i]) - zero[i]));
  return p;
}

int Calibration::saturated(const TactileFrame& f) const {
  check_size(f, sensor);
  return static_cast<int>(
      std::count_if(f.counts.begin(), f.counts.end(), [&](std::uint16_t c) { return c >= saturation_counts; }));
}

void Calibration::tare(std::span<const TactileFrame> unloaded) {
  if (unloaded.empty()) throw Error("tare: no unloaded frames to re-zero from");
  std::vector<double> sum(zero.size(), 0.0);
  for (const auto& f : unloaded) {
    check_size(f, sensor);
    for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += f.counts[i];
  }
  for (std::size_t i = 0; i < sum.size(); ++i)
    zero[i] = static_cast<float>(sum[i] / static_cast<double>(unloaded.size()));
}

std::vector<std::uint16_t> Calibration::to_counts(std::span<const float> pressure) const {
  if (pressure.size() != zero.size())
    throw Error("pressure image has " + std::to_string(pressure.size()) + " values, the calibration " +
                std::to_string(zero.size()));
  std::vector<std::uint16_t> counts(pressure.size());
  for (std::size_t i = 0; i < counts.size(); ++i) {
    if (!std::isfinite(pressure[i]) || gain[i] <= 0)
      throw Error("cannot encode pressure " + std::to_string(pressure[i]) + " kPa at element " + std::to_string(i));
    const double c = std::round(zero[i] + static_cast<double>(pressure[i]) / gain[i]);
    counts[i] = static_cast<std::uint16_t>(std::clamp(c, 0.0, 65535.0));
  }
  return counts;
}

}  // namespace sva::drivers
