#include <sva/drivers/calibration.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include <sva/io/json.hpp>
#include <sva/io/text_file.hpp>

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
  if (io::json_depth(text) > io::kMaxJsonDepth) throw Error(source + ": " + io::json_too_deep_message());
  nlohmann::json j;
  try {
    j = io::parse_json(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(source + ": invalid JSON: " + e.what());
  }
  if (!j.is_object()) throw Error(source + ": expected a JSON object");
  Calibration c;
  auto floats = [&](const char* key) {
    const auto& a = j.at(key);
    if (!a.is_array()) throw Error(source + ": " + key + " must be an array of numbers");
    std::vector<float> out;
    for (const auto& v : a) {
      const auto f = io::json_float(v);
      if (!f) throw Error(source + ": " + key + " holds a non-numeric, non-finite or out-of-range value");
      out.push_back(*f);
    }
    return out;
  };
  try {
    const auto rows = io::json_int(j.at("rows"), 1, 255), cols = io::json_int(j.at("cols"), 1, 255);
    if (!rows || !cols) throw Error(source + ": rows/cols must be in [1, 255]");
    c.sensor.rows = *rows;
    c.sensor.cols = *cols;
    c.sensor.pitch_mm = j.at("pitch_mm").get<double>();
    c.gain = floats("gain_kpa_per_count");
    c.zero = floats("zero_counts");
    const auto saturation = io::json_int(j.value("saturation_counts", nlohmann::json(65535)), 1, 65535);
    if (!saturation) throw Error(source + ": saturation_counts must be in [1, 65535]");
    c.saturation_counts = static_cast<std::uint16_t>(*saturation);
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
  return io::dump_json(j);
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

namespace {

std::string kpa_text(double kpa) {
  std::ostringstream o;
  o << kpa << " kPa";
  return o.str();
}

std::string element_name(const SensorSpec& s, std::size_t i) {
  return "element " + std::to_string(i) + " (row " + std::to_string(static_cast<int>(i) / s.cols) + ", col " +
         std::to_string(static_cast<int>(i) % s.cols) + ")";
}

// The loads a fit can use: finite, positive, each with frames of the calibration's size and nothing saturated.
void check_loads(const Calibration& c, std::span<const LoadFrames> loads) {
  if (loads.empty()) throw Error("gain fit: no loads (give at least one known pressure above 0 kPa)");
  for (const auto& load : loads) {
    if (!std::isfinite(load.kpa) || load.kpa <= 0)
      throw Error("gain fit: load " + kpa_text(load.kpa) + " must be a finite pressure above 0 kPa");
    if (load.frames.empty()) throw Error("gain fit: load " + kpa_text(load.kpa) + " has no frames");
    for (const auto& f : load.frames) {
      check_size(f, c.sensor);
      for (std::size_t i = 0; i < f.counts.size(); ++i)
        if (f.counts[i] >= c.saturation_counts)
          throw Error("gain fit: " + element_name(c.sensor, i) + " is saturated under " + kpa_text(load.kpa) +
                      " (counts " + std::to_string(f.counts[i]) + " >= " + std::to_string(c.saturation_counts) +
                      "): use lighter loads");
    }
  }
}

// Each element's mean and standard deviation over the unloaded frames.
void zero_statistics(const Calibration& c, std::span<const TactileFrame> unloaded, std::vector<double>& mean,
                     std::vector<double>& sigma) {
  if (unloaded.empty()) throw Error("gain fit: no unloaded frames to take the zero from");
  const auto n = static_cast<std::size_t>(c.sensor.elements());
  mean.assign(n, 0.0);
  sigma.assign(n, 0.0);
  for (const auto& f : unloaded) {
    check_size(f, c.sensor);
    for (std::size_t i = 0; i < n; ++i) mean[i] += f.counts[i];
  }
  for (auto& m : mean) m /= static_cast<double>(unloaded.size());
  for (const auto& f : unloaded)
    for (std::size_t i = 0; i < n; ++i) sigma[i] += (f.counts[i] - mean[i]) * (f.counts[i] - mean[i]);
  for (auto& s : sigma) s = std::sqrt(s / static_cast<double>(unloaded.size()));
}

// The mean rise above zero of element i under the heaviest load: how well its slope is determined.
double heaviest_rise(std::span<const LoadFrames> loads, std::size_t i, double zero) {
  const auto heaviest = std::max_element(loads.begin(), loads.end(),
                                         [](const LoadFrames& a, const LoadFrames& b) { return a.kpa < b.kpa; });
  double rise = 0;
  for (const auto& f : heaviest->frames) rise += f.counts[i] - zero;
  return rise / static_cast<double>(heaviest->frames.size());
}

// Least squares through the zero: gain = sum(p d) / sum(d^2), d = counts - zero; returns the element's sum of
// squared residuals in *sse.
double fit_element(std::span<const LoadFrames> loads, std::size_t i, double zero, double* sse) {
  double pd = 0, dd = 0, pp = 0;
  for (const auto& load : loads)
    for (const auto& f : load.frames) {
      const double d = f.counts[i] - zero;
      pd += load.kpa * d;
      dd += d * d;
      pp += load.kpa * load.kpa;
    }
  const double gain = pd / dd;
  *sse = std::max(0.0, pp - gain * pd);  // sum (p - g d)^2 at the optimum
  return gain;
}

}  // namespace

GainFit fit_gains(Calibration& c, std::span<const TactileFrame> unloaded, std::span<const LoadFrames> loads,
                  const GainFitOptions& options) {
  check_loads(c, loads);
  std::vector<double> zero, sigma;
  zero_statistics(c, unloaded, zero, sigma);
  GainFit fit;
  double load_sq = 0;
  for (const auto& load : loads) {
    fit.frames += load.frames.size();
    load_sq += load.kpa * load.kpa * static_cast<double>(load.frames.size());
  }
  std::vector<double> kpa;
  for (const auto& load : loads) kpa.push_back(load.kpa);
  std::sort(kpa.begin(), kpa.end());
  fit.loads = static_cast<int>(std::unique(kpa.begin(), kpa.end()) - kpa.begin());
  std::vector<float> gain(zero.size());
  double total_sse = 0;
  for (std::size_t i = 0; i < zero.size(); ++i) {
    const double rise = heaviest_rise(loads, i, zero[i]);
    const double needed = std::max(options.min_response_counts, options.min_response_sigmas * sigma[i]);
    if (!(rise >= needed)) {
      std::ostringstream why;
      why << "gain fit: " << element_name(c.sensor, i) << (rise < 0 ? " falls " : " rises only ") << std::abs(rise)
          << " counts " << (rise < 0 ? "below" : "above") << " its zero under " << kpa[fit.loads - 1]
          << " kPa (needs >= " << needed << ": its unloaded noise is " << sigma[i]
          << " counts): its gain cannot be fitted (ill-conditioned; a dead element, a load that misses it, or loads "
             "too light)";
      throw Error(why.str());
    }
    double sse = 0;
    gain[i] = static_cast<float>(fit_element(loads, i, zero[i], &sse));
    total_sse += sse;
    const double element_rms = std::sqrt(sse / static_cast<double>(fit.frames));
    if (element_rms >= fit.worst_residual_kpa) {
      fit.worst_residual_kpa = element_rms;
      fit.worst_element = static_cast<int>(i);
    }
  }
  fit.rms_residual_kpa = std::sqrt(total_sse / static_cast<double>(fit.frames * zero.size()));
  fit.relative_residual = fit.rms_residual_kpa / std::sqrt(load_sq / static_cast<double>(fit.frames));
  if (fit.relative_residual > options.max_relative_residual) {
    std::ostringstream why;
    why << "gain fit: residual " << fit.rms_residual_kpa << " kPa RMS is " << 100 * fit.relative_residual
        << "% of the loads (limit " << 100 * options.max_relative_residual << "%; worst "
        << element_name(c.sensor, static_cast<std::size_t>(fit.worst_element)) << ", " << fit.worst_residual_kpa
        << " kPa): the counts do not follow the loads linearly (a load not flat over the array, or presses that do "
           "not match the load list)";
    throw Error(why.str());
  }
  const auto [lo, hi] = std::minmax_element(gain.begin(), gain.end());
  fit.min_gain = *lo;
  fit.max_gain = *hi;
  c.gain = std::move(gain);
  for (std::size_t i = 0; i < zero.size(); ++i) c.zero[i] = static_cast<float>(zero[i]);
  return fit;
}

}  // namespace sva::drivers
