#include "training/calibration_fit.hpp"

#include <sva/base/portable_math.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <cmath>

namespace sva {

namespace {

// The top-label fit's ridge on its slope, per step: light (thousands of steps), enough to keep a regime whose steps
// are nearly all right or all wrong finite.
constexpr double kTopLabelRidge = 1e-3;

// Negative log-likelihood (nats) of the true objects under temperature scale and power.
double temperature_nll(const std::vector<CalibrationSession>& sessions, double scale, double power,
                       double surface_weight) {
  Calibration c;
  c.temperature_scale = scale;
  c.temperature_power = power;
  c.surface_weight = surface_weight;
  double nll = 0.0;
  for (const CalibrationSession& s : sessions) {
    if (!s.known) continue;
    for (const EvidenceLevel& level : s.steps) {
      if (level.readings < 2 || s.object >= level.object_log2_mass.size()) continue;
      const std::vector<double> p = c.object_probability(level, {});
      nll -= pmath::log(std::max(p[s.object], 1e-300));
    }
  }
  return nll;
}

// Solves the small symmetric system a x = b (Gaussian elimination with partial pivoting); false when singular.
template <std::size_t N>
bool solve(std::array<std::array<double, N>, N> a, std::array<double, N> b, std::array<double, N>* x) {
  for (std::size_t c = 0; c < N; ++c) {
    std::size_t p = c;
    for (std::size_t r = c + 1; r < N; ++r)
      if (std::abs(a[r][c]) > std::abs(a[p][c])) p = r;
    if (!(std::abs(a[p][c]) > 1e-300)) return false;
    std::swap(a[p], a[c]);
    std::swap(b[p], b[c]);
    for (std::size_t r = c + 1; r < N; ++r) {
      const double f = a[r][c] / a[c][c];
      for (std::size_t k = c; k < N; ++k) a[r][k] -= f * a[c][k];
      b[r] -= f * b[c];
    }
  }
  for (std::size_t c = N; c-- > 0;) {
    double v = b[c];
    for (std::size_t k = c + 1; k < N; ++k) v -= a[c][k] * (*x)[k];
    (*x)[c] = v / a[c][c];
  }
  return true;
}

// Logistic regression of `y` on x (x[.][0] the bias), with a ridge on the slopes (not on the bias) and, when
// `balanced`, the two classes weighted equally. `start`: the first iterate.
template <std::size_t K>
std::array<double, K> fit_logistic(const std::vector<std::array<double, K>>& x, const std::vector<bool>& unknown,
                                   bool balanced = true, double ridge = 1e-2, std::array<double, K> start = {}) {
  double n1 = 0.0, n0 = 0.0;
  for (bool u : unknown) (u ? n1 : n0) += 1.0;
  if (!balanced) n1 = n0 = 0.5 * (n1 + n0);  // every step the same weight
  std::array<double, K> w = start;
  for (int it = 0; it < 50; ++it) {
    std::array<std::array<double, K>, K> h{};
    std::array<double, K> g{};
    for (std::size_t i = 0; i < x.size(); ++i) {
      const std::array<double, K>& f = x[i];
      double z = 0.0;
      for (std::size_t k = 0; k < K; ++k) z += w[k] * f[k];
      const double p = 1.0 / (1.0 + pmath::exp(-std::clamp(z, -700.0, 700.0)));
      const double weight = unknown[i] ? 0.5 / n1 : 0.5 / n0;
      const double y = unknown[i] ? 1.0 : 0.0;
      for (std::size_t a = 0; a < K; ++a) {
        g[a] += weight * (p - y) * f[a];
        for (std::size_t b = 0; b < K; ++b) h[a][b] += weight * p * (1.0 - p) * f[a] * f[b];
      }
    }
    for (std::size_t k = 1; k < K; ++k) {
      g[k] += ridge * w[k];
      h[k][k] += ridge;
    }
    h[0][0] += 1e-9;
    std::array<double, K> step{};
    if (!solve(h, g, &step)) break;
    double size = 0.0;
    for (std::size_t k = 0; k < K; ++k) {
      w[k] -= step[k];
      size = std::max(size, std::abs(step[k]));
    }
    if (size < 1e-10) break;
  }
  return w;
}

// A pooled model's inputs at one step: the bias and the features, then both again times log(n - 1), so that every
// coefficient is linear in the log of the reading count.
template <std::size_t F>
std::array<double, 2 * (F + 1)> pooled(const std::array<double, F>& f, std::size_t readings) {
  const double l = pmath::log(static_cast<double>(readings - 1));
  std::array<double, 2 * (F + 1)> x{1.0};
  for (std::size_t k = 0; k < F; ++k) x[k + 1] = f[k];
  for (std::size_t k = 0; k <= F; ++k) x[F + 1 + k] = l * x[k];
  return x;
}

// The evidence model's features: those of earlier builds (the evidence per pair, the gap, the fit cost share, 0
// before the fine pose). The fit model's: log2(kFitShareFloor + the share, at most kFitShareCap), from the fine pose
// on.
std::array<double, 3> evidence_features(const EvidenceLevel& level) {
  const auto f = Calibration::unknown_features(level, UnknownFeatureSet::evidence_gap_share);
  return {f[0], f[1], f[2]};
}
std::array<double, 1> fit_features(const EvidenceLevel& level) { return {Calibration::unknown_features(level)[3]}; }

// A pooled model's coefficients at n readings.
template <std::size_t K>
std::array<double, K / 2> at_readings(const std::array<double, K>& w, std::size_t n) {
  const double l = pmath::log(static_cast<double>(n - 1));
  std::array<double, K / 2> c{};
  for (std::size_t k = 0; k < K / 2; ++k) c[k] = w[k] + l * w[K / 2 + k];
  return c;
}

// The temperature of least NLL at one surface weight: a grid over the power, golden-section over log2 scale (the
// likelihood is unimodal in the scale at a fixed power). Returns the NLL.
double fit_temperature_at(const std::vector<CalibrationSession>& sessions, double surface_weight, double* scale,
                          double* power) {
  constexpr double kPhi = 0.6180339887498949;
  double best_nll = INFINITY;
  *scale = Calibration::kDefaultScale;
  *power = Calibration::kDefaultPower;
  for (int step = 0; step <= 50; ++step) {
    const double p = 0.05 * step;
    double lo = -12.0, hi = 3.0;  // log2 scale
    double m1 = hi - kPhi * (hi - lo), m2 = lo + kPhi * (hi - lo);
    auto nll = [&](double log2_scale) { return temperature_nll(sessions, pmath::exp2(log2_scale), p, surface_weight); };
    double f1 = nll(m1), f2 = nll(m2);
    for (int it = 0; it < 40; ++it) {
      if (f1 < f2) {
        hi = m2, m2 = m1, f2 = f1;
        m1 = hi - kPhi * (hi - lo);
        f1 = nll(m1);
      } else {
        lo = m1, m1 = m2, f1 = f2;
        m2 = lo + kPhi * (hi - lo);
        f2 = nll(m2);
      }
    }
    const double f = std::min(f1, f2);
    if (f < best_nll) best_nll = f, *scale = pmath::exp2(f1 < f2 ? m1 : m2), *power = p;
  }
  return best_nll;
}

bool any_surface_fit(const std::vector<CalibrationSession>& sessions) {
  for (const CalibrationSession& s : sessions)
    for (const EvidenceLevel& level : s.steps)
      if (!level.surface_log2_fit.empty()) return true;
  return false;
}

}  // namespace

namespace {

// Platt scaling of the top object after `tempered`'s temperature, per regime: over the known sessions' steps from 2
// readings on that `regime_of` puts in regime 0 or 1 (-1: none). A regime without both right and wrong steps keeps
// `labels`' own.
template <class RegimeOf>
void fit_top_labels(const std::vector<CalibrationSession>& sessions, const Calibration& tempered, RegimeOf regime_of,
                    std::array<Calibration::TopLabel, 2>* labels) {
  std::array<std::vector<std::array<double, 2>>, 2> x;
  std::array<std::vector<bool>, 2> right;
  for (const CalibrationSession& s : sessions) {
    if (!s.known) continue;
    for (const EvidenceLevel& level : s.steps) {
      const int regime = regime_of(level);
      if (level.readings < 2 || s.object >= level.object_log2_mass.size() || regime < 0) continue;
      const std::vector<double> p = tempered.object_probability(level, {});
      const std::size_t top = static_cast<std::size_t>(std::max_element(p.begin(), p.end()) - p.begin());
      x[regime].push_back({1.0, Calibration::top_logit(p[top])});
      right[regime].push_back(top == s.object);
    }
  }
  for (int regime = 0; regime < 2; ++regime) {
    // A regime needs right and wrong steps to say how far its probabilities are off.
    const auto hits = std::count(right[regime].begin(), right[regime].end(), true);
    if (hits == 0 || hits == static_cast<std::ptrdiff_t>(right[regime].size())) continue;
    const std::array<double, 2> w = fit_logistic(x[regime], right[regime], false, kTopLabelRidge, {0.0, 1.0});
    if (Calibration::valid_bias(w[0]) && Calibration::valid_slope(w[1])) (*labels)[regime] = {w[0], w[1]};
  }
}

// The sessions as light estimates see them: every step without its fine pose and surface check.
std::vector<CalibrationSession> light_view(std::vector<CalibrationSession> sessions) {
  for (CalibrationSession& s : sessions)
    for (EvidenceLevel& level : s.steps) {
      level.fit_cost_share = -1.0;
      level.fine_pose_from = 0;
      level.surface_log2_fit.clear();
    }
  return sessions;
}

// The first reading count at which the sessions have a fine pose; 0: none has one.
std::uint32_t first_fine_pose(const std::vector<CalibrationSession>& sessions) {
  std::size_t first = 0;
  for (const CalibrationSession& s : sessions)
    for (const EvidenceLevel& level : s.steps)
      if (level.fit_cost_share >= 0.0 && (first == 0 || level.readings < first)) first = level.readings;
  return static_cast<std::uint32_t>(first);
}

}  // namespace

void fit_top_label(const std::vector<CalibrationSession>& sessions, Calibration* calibration) {
  Calibration tempered = *calibration;
  tempered.top_label = Calibration{}.top_label;
  calibration->top_label = Calibration{}.top_label;
  fit_top_labels(
      sessions, tempered, [](const EvidenceLevel& level) { return level.fit_cost_share >= 0.0 ? 1 : 0; },
      &calibration->top_label);
}

void fit_light(const std::vector<CalibrationSession>& tempering, const std::vector<CalibrationSession>& sessions,
               Calibration* calibration) {
  calibration->light = {};
  const std::uint32_t from = first_fine_pose(tempering);
  if (from == 0) return;  // light and full estimates are the same on every step
  // The light view's own calibration, learned as the full one is: its temperature over every step (before `from`
  // the two views are the same steps), its top label over the steps it applies to, "none of these" from the evidence.
  Calibration light;
  const std::vector<CalibrationSession> view = light_view(tempering);
  fit_temperature(view, &light);
  std::array<Calibration::TopLabel, 2> labels = Calibration{}.top_label;
  fit_top_labels(
      view, light, [from](const EvidenceLevel& level) { return level.readings >= from ? 0 : -1; }, &labels);
  fit_unknown(light_view(sessions), &light);
  calibration->light = {.from = from,
                        .temperature_scale = light.temperature_scale,
                        .temperature_power = light.temperature_power,
                        .top_label = labels[0],
                        .unknown = light.unknown};
}

void fit_temperature(const std::vector<CalibrationSession>& sessions, Calibration* calibration) {
  // The surface weight on a grid of halvings (the NLL is flat near its best; a coarse grid is enough), each with its
  // own temperature. Sessions without a surface check keep the default weight.
  std::vector<double> weights{Calibration::kDefaultSurfaceWeight};
  if (any_surface_fit(sessions)) weights = {0.0, 1.0 / 32, 1.0 / 16, 1.0 / 8, 1.0 / 4, 1.0 / 2, 1.0};
  double best_nll = INFINITY;
  for (double w : weights) {
    double scale = 0.0, power = 0.0;
    const double nll = fit_temperature_at(sessions, w, &scale, &power);
    if (nll < best_nll) {
      best_nll = nll;
      calibration->temperature_scale = scale;
      calibration->temperature_power = power;
      calibration->surface_weight = w;
    }
  }
}

void fit_unknown(const std::vector<CalibrationSession>& sessions, Calibration* calibration) {
  calibration->unknown = {};
  std::size_t readings = 0;
  bool any_unknown = false, any_known = false;
  std::vector<std::array<double, 8>> evidence;  // every step
  std::vector<std::array<double, 4>> fit;       // the steps with a fine pose
  std::vector<bool> evidence_unknown, fit_unknown;
  for (const CalibrationSession& s : sessions) {
    readings = std::max(readings, s.steps.size());
    (s.known ? any_known : any_unknown) = true;
    for (const EvidenceLevel& level : s.steps) {
      if (level.readings < 2) continue;
      evidence.push_back(pooled(evidence_features(level), level.readings));
      evidence_unknown.push_back(!s.known);
      if (level.fit_cost_share < 0.0) continue;
      fit.push_back(pooled(fit_features(level), level.readings));
      fit_unknown.push_back(!s.known);
    }
  }
  if (!any_unknown || !any_known || readings < 2) return;
  const std::array<double, 8> we = fit_logistic(evidence, evidence_unknown);
  const bool has_fit = std::count(fit_unknown.begin(), fit_unknown.end(), true) > 0 &&
                       std::count(fit_unknown.begin(), fit_unknown.end(), false) > 0;
  // Sessions too short for a fine pose: the evidence model alone, as earlier builds read it.
  if (!has_fit) calibration->unknown.features = UnknownFeatureSet::evidence_gap_share;
  const std::array<double, 4> wf = has_fit ? fit_logistic(fit, fit_unknown) : std::array<double, 4>{};
  // Written out per reading count (the map's form), to twice the sessions' length; past that, the last. One row
  // holds both models, as the features of each side are 0 on the other (calibration.hpp): the evidence model's bias
  // and weights, then the fit model's bias less the evidence model's (the indicator's weight) and its slope.
  for (std::size_t n = 2; n <= 2 * readings; ++n) {
    const std::array<double, 4> e = at_readings(we, n);
    const std::array<double, 2> f = at_readings(wf, n);
    calibration->unknown.per_readings.push_back(has_fit ? UnknownCoefficients{e[0], e[1], e[2], f[0] - e[0], f[1]}
                                                        : UnknownCoefficients{e[0], e[1], e[2], e[3], 0.0});
  }
}

namespace {

// A calibration map of `split`'s known objects, with their surfaces when the map has them: its sessions then verify
// as the map's own recognizer will, and the surface weight is learned for that model.
std::shared_ptr<PairMap> calibration_map(const CalibrationSplit& split, const TrainParameters& params,
                                         const std::vector<ObjectSurface>& surfaces) {
  std::shared_ptr<PairMap> map = train_pair_map(split.map_part, params, nullptr);
  if (surfaces.empty()) return map;
  map->surfaces.resize(map->objects.size());
  for (std::size_t o = 0; o < split.map_object.size(); ++o)
    if (split.map_object[o] >= 0) map->surfaces[static_cast<std::size_t>(split.map_object[o])] = surfaces[o];
  return map;
}

}  // namespace

Calibration learn_calibration(const Dataset& data, const TrainParameters& params, const CalibrationOptions& options) {
  TrainParameters p = params;
  p.progress = false;  // one bar per set of sessions
  HeldOutSessionOptions so = options.sessions;
  so.seed = params.seed;
  so.threads = params.threads;
  so.progress = params.progress;
  // "None of these" learns from objects the map does not hold: a fifth of them held out whole.
  const CalibrationSplit split = split_for_calibration(data, options.held_out_share, params.seed);
  const std::vector<CalibrationSession> sessions =
      run_held_out_sessions(*calibration_map(split, p, options.surfaces), split, so);
  // The temperature and the top label learn from a map of every object, its readings alone held out: a map missing a
  // fifth of the objects faces fewer look-alikes than the real one, and its sessions were surer than the map's own
  // (lookalikes: docs/evaluation.md, "The temperature from a map of every object, and the top label"). Without objects
  // held out (fewer than three) the first map is already that map.
  std::vector<CalibrationSession> every;
  if (std::count(split.map_object.begin(), split.map_object.end(), -1) > 0) {
    const CalibrationSplit all = split_for_calibration(data, options.held_out_share, params.seed, false);
    HeldOutSessionOptions known = so;
    known.unknown_sessions = 0;
    every = run_held_out_sessions(*calibration_map(all, p, options.surfaces), all, known);
  }
  const std::vector<CalibrationSession>& tempering = every.empty() ? sessions : every;
  Calibration c;
  fit_temperature(tempering, &c);
  fit_top_label(tempering, &c);
  fit_unknown(sessions, &c);
  fit_light(tempering, sessions, &c);
  c.learned = true;
  for (const CalibrationSession& s : sessions) ++(s.known ? c.known_sessions : c.unknown_sessions);
  c.session_readings = static_cast<std::uint32_t>(so.readings);
  return c;
}

}  // namespace sva
