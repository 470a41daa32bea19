#include <sva/eval/report.hpp>
#include "eval/table_cell.hpp"

#include "eval/metrics.hpp"

#include <sva/base/so3.hpp>
#include <sva/error.hpp>
#include <sva/io/text_file.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>
#include <sva/io/json.hpp>

namespace sva::eval {

using nlohmann::json;

namespace {

json opt(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// Translation (mm) and rotation vector (rad): six CSV cells.
std::string pose_cells(const RigidPose& p) {
  const glm::dvec3 r = so3::log_sincos(p.R);
  return num(p.T.x) + ',' + num(p.T.y) + ',' + num(p.T.z) + ',' + num(r.x) + ',' + num(r.y) + ',' + num(r.z);
}

std::string csv_quote(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

// Votes that round to zero mass are counted, never silently dropped: one line
// with their share of all votes, so a run whose evidence vanishes shows it.
std::string zero_votes_line(const Curve& curve) {
  std::uint64_t votes = 0, zero = 0;
  for (const auto& p : curve.points) {
    votes += p.votes;
    zero += p.votes_zero;
  }
  if (votes == 0) return "";
  char line[200];
  std::snprintf(line, sizeof line,
                "votes: %llu inside the pose space, %llu (%.3g%%) of mass 0 (below half a 2^-24 unit)\n",
                static_cast<unsigned long long>(votes), static_cast<unsigned long long>(zero),
                100.0 * static_cast<double>(zero) / static_cast<double>(votes));
  return line;
}

// A statistic as JSON: "NAME" (the median), "NAME_mean", "NAME_p90".
void put_spread(json& j, const std::string& name, const Spread& s) {
  j[name] = opt(s.median);
  j[name + "_mean"] = opt(s.mean);
  j[name + "_p90"] = opt(s.p90);
}

// Three cells: median, mean, p90.
std::string spread_cells(const Spread& s, const char* fmt) {
  char buf[96];
  std::snprintf(buf, sizeof buf, " %8s %8s %8s", cell(s.median, fmt).c_str(), cell(s.mean, fmt).c_str(),
                cell(s.p90, fmt).c_str());
  return buf;
}

// The readings-to-95% metric and, for the active policies, the plan's cost: one line under the table.
std::string confidence_line(const Curve& curve) {
  const Confidence& c = curve.to_95;
  if (c.trials == 0) return "";
  char line[512];
  std::snprintf(line, sizeof line,
                "policy %s: readings until the true object holds >= %.0f%%: mean %s, median %s (%zu of %zu trials "
                "got there",
                curve.policy.c_str(), 100.0 * c.threshold, cell(c.mean, "%.2f").c_str(), cell(c.median, "%.1f").c_str(),
                c.reached, c.trials);
  std::string s = line;
  if (c.reached < c.trials) s += "; the others count as " + std::to_string(curve.points.size() + 1);
  s += ")";
  if (curve.plan_ms) {
    std::snprintf(line, sizeof line, "; median plan %.3f ms", *curve.plan_ms);
    s += line;
  }
  return s + "\n";
}

json confidence_json(const Confidence& c) {
  return {{"threshold", c.threshold},
          {"trials", c.trials},
          {"reached", c.reached},
          {"mean", opt(c.mean)},
          {"median", opt(c.median)}};
}

json calibration_json(const CalibrationSummary& c) {
  json bins = json::array();
  for (const ReliabilityBin& b : c.bins)
    bins.push_back({{"count", b.count}, {"confidence", b.confidence}, {"accuracy", b.accuracy}});
  json ranges = json::array();
  for (const ReadingRangeCalibration& r : c.by_readings)
    ranges.push_back({{"readings", {r.first, r.last}},
                      {"trial_readings", r.trial_readings},
                      {"ece", r.ece},
                      {"confidence", r.confidence},
                      {"accuracy", r.accuracy}});
  return {{"trial_readings", c.trial_readings},
          {"ece", c.ece},
          {"ece_interval", {c.ece_interval[0], c.ece_interval[1]}},
          {"ece_if_calibrated",
           {{"independent", c.ece_if_calibrated_independent}, {"per_trial", c.ece_if_calibrated_per_trial}}},
          {"confidently_wrong", c.confidently_wrong},
          {"reliability", std::move(bins)},
          {"by_readings", std::move(ranges)}};
}

json stop_json(const StopSummary& s) {
  return {{"threshold", s.threshold},
          {"trials", s.trials},
          {"decided", s.decided},
          {"right", s.right},
          {"accuracy", opt(s.accuracy)},
          {"mean_readings", opt(s.mean_readings)},
          {"mean_readings_to_right", s.mean_readings_to_right}};
}

json unknown_json(const UnknownSummary& u) {
  json roc = json::array();
  for (const auto& [fpr, tpr] : u.roc) roc.push_back({fpr, tpr});
  return {{"readings", u.readings},
          {"known_trials", u.known_trials},
          {"unknown_trials", u.unknown_trials},
          {"auc", u.auc},
          {"caught_at_5", u.caught_at_5},
          {"threshold_at_5", u.threshold_at_5},
          {"rejected_at_5", u.rejected_at_5},
          {"roc", std::move(roc)}};
}

// Where the ECE comes from: each range of reading counts, its ECE and which way it errs (mean confidence against the
// share right).
std::string range_line(const std::vector<ReadingRangeCalibration>& ranges) {
  std::string out = "  by readings:";
  char part[128];
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    const ReadingRangeCalibration& r = ranges[i];
    std::snprintf(part, sizeof part, "%s %zu-%zu ECE %.3f (mean p %.2f, %.0f%% right)", i ? "," : "", r.first, r.last,
                  r.ece, r.confidence, 100.0 * r.accuracy);
    out += part;
  }
  return out + "\n";
}

// The probability lines under the table: calibration, stopping, objects outside the map.
std::string probability_lines(const Curve& curve) {
  char line[512];
  const CalibrationSummary& c = curve.calibration;
  std::string out;
  if (c.trial_readings > 0) {
    std::snprintf(line, sizeof line,
                  "calibration: ECE %.4f, confidently wrong (top >= 0.99, wrong) %.2f%% of %zu trial-readings from 2 "
                  "readings on\n",
                  c.ece, 100.0 * c.confidently_wrong, c.trial_readings);
    out += line;
    std::snprintf(line, sizeof line,
                  "  ECE over resampled trials %.4f-%.4f (90%%); exactly right probabilities would measure %.4f "
                  "(readings independent) to %.4f (one outcome per trial)\n",
                  c.ece_interval[0], c.ece_interval[1], c.ece_if_calibrated_independent, c.ece_if_calibrated_per_trial);
    out += line;
    out += range_line(c.by_readings);
  }
  if (curve.stop) {
    const StopSummary& s = *curve.stop;
    if (s.accuracy && s.mean_readings)
      std::snprintf(line, sizeof line,
                    "stop at %.3g: %zu of %zu trials decided, %.1f%% of them right, after %.2f readings on average; "
                    "%.2f readings to a right decision (a wrong or no decision counts %zu)\n",
                    s.threshold, s.decided, s.trials, 100.0 * *s.accuracy, *s.mean_readings, s.mean_readings_to_right,
                    curve.points.size() + 1);
    else
      std::snprintf(line, sizeof line, "stop at %.3g: none of %zu trials decided\n", s.threshold, s.trials);
    out += line;
  }
  if (curve.unknown) {
    const UnknownSummary& u = *curve.unknown;
    std::snprintf(
        line, sizeof line,
        "none of these at %zu readings: ROC area %.3f; %.1f%% of %zu unseen-object trials caught at p_unknown "
        ">= %.3g, which rejects %.1f%% of %zu known-object trials\n",
        u.readings, u.auc, 100.0 * u.caught_at_5, u.unknown_trials, u.threshold_at_5, 100.0 * u.rejected_at_5,
        u.known_trials);
    out += line;
  }
  return out;
}

}  // namespace

std::string to_json(const EvalResult& result, const Curve& curve) {
  json j;
  j["scene"] = result.scene;
  j["backend"] = result.backend;
  j["method"] = result.method;
  j["policy"] = result.policy;
  j["estimate"] = result.estimate;
  j["trials"] = result.trials.size();
  j["seed"] = result.seed;
  j["max_readings"] = result.max_readings;
  j["objects"] = result.objects;
  json points = json::array();
  for (const auto& p : curve.points) {
    json q = {{"readings", p.readings}, {"accuracy", p.accuracy}, {"pose_trials", p.pose_trials}};
    put_spread(q, "translation_error_mm", p.translation_mm);
    put_spread(q, "angular_error_deg", p.angular_deg);
    put_spread(q, "inertial_error_mm", p.inertial_mm);
    put_spread(q, "mssd_mm", p.mssd_mm);
    put_spread(q, "adds_mm", p.adds_mm);
    put_spread(q, "update_ms", p.update_ms);
    q["update_ms_p95"] = opt(p.update_ms_p95);
    q["votes"] = p.votes;
    q["votes_zero"] = p.votes_zero;
    points.push_back(std::move(q));
  }
  j["curve"] = std::move(points);
  j["readings_to_95"] = confidence_json(curve.to_95);
  j["plan_ms_median"] = opt(curve.plan_ms);
  j["calibration"] = calibration_json(curve.calibration);
  if (curve.stop) j["stop"] = stop_json(*curve.stop);
  if (curve.unknown) j["unknown_objects"] = unknown_json(*curve.unknown);
  return io::dump_json(j, 2) + "\n";
}

std::string to_csv(const EvalResult& result) {
  std::ostringstream s;
  s << "trial,object,object_name,readings,sample,estimated_object,correct,true_object_probability,pose_valid,"
       "translation_error_mm,angular_error_deg,inertial_error_mm,update_ms,"
       "true_tx,true_ty,true_tz,true_rx,true_ry,true_rz,est_tx,est_ty,est_tz,est_rx,est_ry,est_rz,votes,votes_zero,"
       "top_probability,p_unknown,known,mssd_mm,adds_mm\n";
  for (const auto& t : result.trials) {
    const std::string name = t.object < result.objects.size() ? result.objects[t.object] : "";
    for (std::size_t k = 0; k < t.steps.size(); ++k) {
      const StepResult& st = t.steps[k];
      s << t.index << ',' << t.object << ',' << csv_quote(name) << ',' << (k + 1) << ','
        << (k < t.samples.size() && t.samples[k] != std::numeric_limits<std::size_t>::max()
                ? std::to_string(t.samples[k])
                : std::string())
        << ',' << st.estimated_object << ',' << (st.correct ? 1 : 0) << ',' << num(st.true_object_probability) << ','
        << (st.pose_valid ? 1 : 0) << ',';
      if (st.has_pose_error())
        s << num(st.translation_error_mm) << ',' << num(st.angular_error_rad * 180.0 / std::numbers::pi) << ','
          << num(st.inertial_error_mm);
      else
        s << ",,";
      s << ',' << num(st.update_ms) << ',' << pose_cells(t.pose) << ',';
      if (st.pose_valid)
        s << pose_cells(st.estimate);
      else
        s << ",,,,,";
      s << ',' << st.votes << ',' << st.votes_zero << ',' << num(st.top_probability) << ',' << num(st.p_unknown) << ','
        << (t.known ? 1 : 0) << ',' << (st.mssd_mm ? num(*st.mssd_mm) : std::string()) << ','
        << (st.adds_mm ? num(*st.adds_mm) : std::string()) << '\n';
    }
  }
  return s.str();
}

std::string to_evidence_jsonl(const EvalResult& result) {
  std::string out;
  for (const auto& t : result.trials) {
    for (std::size_t k = 0; k < t.steps.size(); ++k) {
      const StepResult& st = t.steps[k];
      nlohmann::json row = {{"trial", t.index},
                            {"readings", k + 1},
                            {"object", t.object < result.objects.size() ? result.objects[t.object] : ""},
                            {"map_object", t.known ? nlohmann::json(t.map_object) : nlohmann::json(nullptr)},
                            {"estimated_object", st.estimated_object},
                            {"correct", st.correct},
                            {"temperature", st.evidence.temperature},
                            {"surface_weight", st.evidence.surface_weight},
                            {"pairs_log2_mass", st.evidence.pairs_log2_mass},
                            {"surface_log2_fit", st.evidence.surface_log2_fit}};
      out += io::dump_json(row) + "\n";
    }
  }
  return out;
}

std::string format_table(const Curve& curve) {
  std::ostringstream s;
  s << "scene " << curve.scene << ", method " << curve.method << ", backend " << curve.backend
    << (curve.estimate == "light" ? ", light estimates" : "") << ", " << curve.trials
    << " trials (errors: median, mean and 90th percentile over trials with the right object)\n";
  // MSSD and ADD-S only where the objects' meshes were read (a result without them prints as it always has).
  bool surface = false;
  for (const auto& p : curve.points) surface = surface || p.mssd_mm.median.has_value();
  char line[512];
  std::snprintf(line, sizeof line, "%25s %-26s %-26s %-26s %s%s\n", "", " translation (mm)", " angle (deg)",
                " inertial (mm)", surface ? " MSSD (mm)                  ADD-S (mm)                 " : "",
                " ms/update (all trials)");
  s << line;
  const char* three = " %8s %8s %8s";
  std::string head = "readings  accuracy  posed";
  for (int k = 0; k < (surface ? 6 : 4); ++k) {
    char buf[64];
    std::snprintf(buf, sizeof buf, three, "median", "mean", "p90");
    head += buf;
  }
  s << head << "      p95\n";
  for (const auto& p : curve.points) {
    std::snprintf(line, sizeof line, "%8zu %8.1f%% %6zu", p.readings, 100.0 * p.accuracy, p.pose_trials);
    s << line << spread_cells(p.translation_mm, "%.2f") << spread_cells(p.angular_deg, "%.2f")
      << spread_cells(p.inertial_mm, "%.2f");
    if (surface) s << spread_cells(p.mssd_mm, "%.2f") << spread_cells(p.adds_mm, "%.2f");
    s << spread_cells(p.update_ms, "%.3f");
    std::snprintf(line, sizeof line, " %8s\n", cell(p.update_ms_p95, "%.3f").c_str());
    s << line;
  }
  s << zero_votes_line(curve) << confidence_line(curve) << probability_lines(curve);
  return s.str();
}

Curve read_curve_json(const std::filesystem::path& file) {
  const std::string name = file.string();
  const std::string text = io::read_text_file(file, "cannot open the evaluation summary");
  json j;
  try {
    j = io::parse_json(text);
  } catch (const json::parse_error& e) {
    throw Error(name + ": invalid JSON: " + e.what());
  }
  auto fail = [&](const std::string& what) -> void { throw Error(name + ": " + what); };
  if (!j.is_object()) fail("expected a JSON object (an sva eval summary)");
  Curve c;
  for (const char* key : {"scene", "backend", "method"})
    if (!j.contains(key) || !j[key].is_string()) fail(std::string("missing or non-string \"") + key + "\"");
  c.scene = j["scene"].get<std::string>();
  c.backend = j["backend"].get<std::string>();
  c.method = j["method"].get<std::string>();
  if (j.contains("policy") && j["policy"].is_string()) c.policy = j["policy"].get<std::string>();
  if (j.contains("estimate") && j["estimate"].is_string()) c.estimate = j["estimate"].get<std::string>();
  c.label = curve_label(c.method, c.policy, c.estimate);
  if (j.contains("readings_to_95") && j["readings_to_95"].is_object()) {
    const json& r = j["readings_to_95"];
    auto get = [&](const char* key) -> std::optional<double> {
      if (!r.contains(key) || !r[key].is_number() || !std::isfinite(r[key].get<double>())) return std::nullopt;
      return r[key].get<double>();
    };
    c.to_95.threshold = get("threshold").value_or(0.95);
    c.to_95.trials = static_cast<std::size_t>(get("trials").value_or(0.0));
    c.to_95.reached = static_cast<std::size_t>(get("reached").value_or(0.0));
    c.to_95.mean = get("mean");
    c.to_95.median = get("median");
  }
  if (j.contains("plan_ms_median") && j["plan_ms_median"].is_number()) c.plan_ms = j["plan_ms_median"].get<double>();
  if (!j.contains("trials") || !j["trials"].is_number_unsigned()) fail("missing or invalid \"trials\"");
  c.trials = j["trials"].get<std::size_t>();
  if (!j.contains("curve") || !j["curve"].is_array()) fail("missing \"curve\" array");
  auto number = [&](const json& p, const char* key, std::size_t i) -> std::optional<double> {
    const std::string where = "curve[" + std::to_string(i) + "]." + key;
    if (!p.contains(key)) fail("missing " + where);
    if (p[key].is_null()) return std::nullopt;
    if (!p[key].is_number() || !std::isfinite(p[key].get<double>())) fail(where + " is not a finite number");
    return p[key].get<double>();
  };
  for (std::size_t i = 0; i < j["curve"].size(); ++i) {
    const json& p = j["curve"][i];
    if (!p.is_object()) fail("curve[" + std::to_string(i) + "] is not an object");
    CurvePoint pt;
    auto readings = number(p, "readings", i);
    auto accuracy = number(p, "accuracy", i);
    if (!readings || *readings < 1 || !accuracy || *accuracy < 0 || *accuracy > 1)
      fail("curve[" + std::to_string(i) + "]: readings must be >= 1 and accuracy in [0, 1]");
    pt.readings = static_cast<std::size_t>(*readings);
    pt.accuracy = *accuracy;
    // The median is required; mean and p90 only in summaries written since they were added.
    auto spread = [&](const std::string& key) {
      Spread s;
      s.median = number(p, key.c_str(), i);
      if (p.contains(key + "_mean")) s.mean = number(p, (key + "_mean").c_str(), i);
      if (p.contains(key + "_p90")) s.p90 = number(p, (key + "_p90").c_str(), i);
      return s;
    };
    pt.translation_mm = spread("translation_error_mm");
    pt.angular_deg = spread("angular_error_deg");
    pt.inertial_mm = spread("inertial_error_mm");
    // Summaries written before the surface errors have none.
    if (p.contains("mssd_mm")) pt.mssd_mm = spread("mssd_mm");
    if (p.contains("adds_mm")) pt.adds_mm = spread("adds_mm");
    pt.update_ms = spread("update_ms");
    pt.update_ms_p95 = number(p, "update_ms_p95", i);
    if (p.contains("pose_trials") && p["pose_trials"].is_number_unsigned())
      pt.pose_trials = p["pose_trials"].get<std::size_t>();
    c.points.push_back(pt);
  }
  return c;
}

std::string describe_surfaces(const MapSummary& map) {
  if (map.surface_objects == 0) return "none: the verify stage weighs the readings against the training contacts";
  char line[256];
  std::snprintf(line, sizeof line, "%zu %s, %zu triangles, %zu vertices, %.2f MB (apart from the entries' bytes)",
                map.surface_objects, map.surface_objects == 1 ? "mesh" : "meshes", map.surface_triangles,
                map.surface_vertices, static_cast<double>(map.surface_bytes) / 1e6);
  return line;
}

std::string describe_calibration(const MapSummary& map) {
  const MapSummary::Calibration& c = map.calibration;
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s: temperature %.3g (n-1)^-%.2f, surface check weight %.3g",
                c.learned ? "learned" : "the default", c.temperature_scale, c.temperature_power, c.surface_weight);
  std::string s = buf;
  const std::array<double, 2> identity{0.0, 1.0};
  if (c.top_label_before != identity || c.top_label_after != identity) {
    std::snprintf(buf, sizeof buf,
                  ", top label: logit p' = %.3g + %.3g logit p before the fine pose, %.3g + %.3g logit p from it on",
                  c.top_label_before[0], c.top_label_before[1], c.top_label_after[0], c.top_label_after[1]);
    s += buf;
  }
  if (c.learned) {
    std::snprintf(buf, sizeof buf, ", from %u + %u held-out sessions of %u readings", c.known_sessions,
                  c.unknown_sessions, c.session_readings);
    s += buf;
  }
  std::snprintf(buf, sizeof buf, ", fine pose from %u readings", c.fine_pose_from);
  s += buf;
  if (!c.unknown_model)
    s += "; cannot say \"none of these\"";
  else
    s += c.unknown_from_fit ? "; says \"none of these\" (from the evidence, then the fine pose's fit)"
                            : "; says \"none of these\" (from the evidence alone)";
  if (c.light_from == 0) return s;
  std::snprintf(buf, sizeof buf,
                "; light estimates from %u readings: temperature %.3g (n-1)^-%.2f, top label %.3g + %.3g logit p%s",
                c.light_from, c.light_temperature_scale, c.light_temperature_power, c.light_top_label[0],
                c.light_top_label[1], c.light_unknown_model ? ", \"none of these\" from the evidence" : "");
  return s + buf;
}

}  // namespace sva::eval
