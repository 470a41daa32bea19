#include <sva/drivers/contact_readings.hpp>
#include <sva/error.hpp>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include <sva/io/json.hpp>

namespace sva::drivers {

namespace {

glm::dvec3 vec3(const nlohmann::json& j, const char* key, const std::string& source) {
  const auto v = j.at(key).get<std::vector<double>>();
  if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
    throw Error(source + ": \"" + key + "\" must be 3 finite numbers");
  return {v[0], v[1], v[2]};
}

std::optional<ControllerStatus> status_from(const std::string& s) {
  for (auto c : {ControllerStatus::converged, ControllerStatus::not_converged, ControllerStatus::no_contact})
    if (s == to_string(c)) return c;
  return std::nullopt;
}

bool same_pose(const PoseSample& a, const PoseSample& b) {
  return a.position == b.position && a.normal == b.normal && a.x_axis == b.x_axis;
}

double mean(const std::vector<float>& p) {
  double s = 0;
  for (float v : p) s += v;
  return p.empty() ? 0.0 : s / static_cast<double>(p.size());
}

std::string seconds(double t) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3f s", t);
  return b;
}

}  // namespace

PoseSample parse_pose_line(const std::string& line, const std::string& source) {
  PoseSample p;
  try {
    const auto j = io::parse_json(line);
    if (!j.is_object()) throw Error(source + ": a pose line must be a JSON object");
    p.time = j.at("time").get<double>();
    if (!std::isfinite(p.time)) throw Error(source + ": \"time\" must be finite");
    p.position = vec3(j, "position", source);
    p.normal = vec3(j, "normal", source);
    p.x_axis = vec3(j, "x_axis", source);
    if (j.contains("status")) {
      p.status = status_from(j.at("status").get<std::string>());
      if (!p.status) throw Error(source + ": unknown status (converged, not_converged or no_contact)");
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(source + ": bad pose line: " + e.what());
  }
  const double nl = glm::length(p.normal), xl = glm::length(p.x_axis);
  if (std::abs(nl - 1.0) > 1e-3 || std::abs(xl - 1.0) > 1e-3 || std::abs(glm::dot(p.normal, p.x_axis)) > 1e-3)
    throw Error(source + ": normal and x_axis must be perpendicular unit vectors");
  return p;
}

std::string pose_line(const PoseSample& p) {
  nlohmann::json j{{"time", p.time},
                   {"position", {p.position.x, p.position.y, p.position.z}},
                   {"normal", {p.normal.x, p.normal.y, p.normal.z}},
                   {"x_axis", {p.x_axis.x, p.x_axis.y, p.x_axis.z}}};
  if (p.status) j["status"] = to_string(*p.status);
  return io::dump_json(j);
}

void SettleRule::validate() const {
  auto bad = [](const char* what) { return Error(std::string("settle rule: ") + what); };
  if (frames < 1 || frames > 10000) throw bad("frames must be in [1, 10000]");
  for (double v : {target_kpa, tolerance_kpa, stable_kpa, contact_kpa, max_pose_gap_s})
    if (!std::isfinite(v) || v < 0) throw bad("values must be finite and non-negative");
  if (!std::isfinite(pose_clock_offset_s) || std::abs(pose_clock_offset_s) > 1e9)
    throw bad("pose_clock_offset_s must be a finite number of seconds (|offset| <= 1e9)");
  if (contact_kpa <= 0) throw bad("contact_kpa must be positive");
}

std::string SettleRule::to_json() const {
  return io::dump_json(nlohmann::json{{"frames", frames},
                                      {"target_kpa", target_kpa},
                                      {"tolerance_kpa", tolerance_kpa},
                                      {"stable_kpa", stable_kpa},
                                      {"contact_kpa", contact_kpa},
                                      {"max_pose_gap_s", max_pose_gap_s},
                                      {"pose_clock_offset_s", pose_clock_offset_s}});
}

SettleRule SettleRule::from_json(const std::string& text, const std::string& source) {
  SettleRule r;
  try {
    const auto j = io::parse_json(text);
    if (j.contains("frames")) {  // range-checked as a double first: get<int>() of 1e300 is undefined
      const auto frames = io::json_int(j.at("frames"), 1, 10000);
      if (!frames) throw Error(source + ": bad settle rule: frames must be a whole number in [1, 10000]");
      r.frames = *frames;
    }
    r.target_kpa = j.value("target_kpa", r.target_kpa);
    r.tolerance_kpa = j.value("tolerance_kpa", r.tolerance_kpa);
    r.stable_kpa = j.value("stable_kpa", r.stable_kpa);
    r.contact_kpa = j.value("contact_kpa", r.contact_kpa);
    r.max_pose_gap_s = j.value("max_pose_gap_s", r.max_pose_gap_s);
    r.pose_clock_offset_s = j.value("pose_clock_offset_s", r.pose_clock_offset_s);  // absent in older recordings
  } catch (const nlohmann::json::exception& e) {
    throw Error(source + ": bad settle rule: " + e.what());
  }
  r.validate();
  return r;
}

ReadingFormer::ReadingFormer(Calibration calibration, SettleRule rule)
    : calibration_(std::move(calibration)), rule_(rule) {
  rule_.validate();
}

void ReadingFormer::note(double time, std::string text) { notes_.push_back({time, std::move(text)}); }

void ReadingFormer::add_frame(const StreamFrame& f) {
  const double t = static_cast<double>(f.host_ns) * 1e-9;
  if (f.missing_before) window_.clear();  // the window must be consecutive frames
  const bool saturated = calibration_.saturated(f.frame) > 0;
  auto pressure = calibration_.to_pressure(f.frame);
  const double m = mean(pressure);
  if (m < rule_.contact_kpa) {
    in_contact_ = settled_ = false;
    window_.clear();
    return;
  }
  in_contact_ = true;
  if (settled_) return;  // one reading per contact
  if (saturated) {
    note(t, "frame " + std::to_string(f.frame.sequence) + " saturated: no reading from it");
    window_.clear();
    return;
  }
  const bool on_target = rule_.target_kpa <= 0 || std::abs(m - rule_.target_kpa) <= rule_.tolerance_kpa;
  bool stable = true;
  if (!window_.empty())
    for (std::size_t i = 0; i < pressure.size() && stable; ++i)
      stable = std::abs(pressure[i] - window_.back()[i]) <= rule_.stable_kpa;
  if (!on_target || !stable) window_.clear();
  if (!on_target) return;
  window_.push_back(std::move(pressure));
  if (static_cast<int>(window_.size()) < rule_.frames) return;
  settled_ = true;
  waiting_.push_back({t, f.frame.sequence, std::move(window_.back())});
  window_.clear();
  resolve_waiting();
}

void ReadingFormer::add_pose(const PoseSample& given) {
  // On the host's clock from here on (the arm's own clock may differ: SettleRule::pose_clock_offset_s).
  PoseSample pose = given;
  pose.time += rule_.pose_clock_offset_s;
  if (!poses_.empty() && pose.time < poses_.back().time)
    throw Error("pose stream: time " + seconds(given.time) + " is earlier than the previous pose's " +
                seconds(poses_.back().time - rule_.pose_clock_offset_s));
  poses_.push_back(pose);
  // Keep the poses a waiting contact or the next one may need.
  const double keep_from = waiting_.empty() ? pose.time - 10.0 : waiting_.front().time - 10.0;
  while (poses_.size() > 2 && poses_[1].time < keep_from) poses_.pop_front();
  resolve_waiting();
}

void ReadingFormer::link_lost(double time) {
  if (in_contact_ && !settled_) note(time, "link lost during a contact: it will not form a reading");
  window_.clear();
  in_contact_ = settled_ = false;
}

void ReadingFormer::poses_ended() {
  poses_ended_ = true;
  resolve_waiting();
}

std::optional<PoseSample> ReadingFormer::pose_at(double t, std::string* why) const {
  if (poses_.empty() || poses_.front().time > t) {
    *why = "no pose at or before it";
    return std::nullopt;
  }
  std::size_t i = 1;
  while (i < poses_.size() && poses_[i].time < t) ++i;
  const PoseSample& a = poses_[i - 1];
  if (a.time == t || i == poses_.size()) return a.time == t ? std::optional(a) : std::nullopt;
  const PoseSample& b = poses_[i];
  if (b.time == t) return b;
  if (b.time - a.time > rule_.max_pose_gap_s) {
    *why = "the poses around it are " + seconds(b.time - a.time) + " apart";
    return std::nullopt;
  }
  if (same_pose(a, b)) return a;  // the arm held still: exactly its pose
  const double w = (t - a.time) / (b.time - a.time);
  PoseSample p = a;
  p.time = t;
  p.position = a.position + w * (b.position - a.position);
  p.normal = glm::normalize(a.normal + w * (b.normal - a.normal));
  const glm::dvec3 x = a.x_axis + w * (b.x_axis - a.x_axis);
  p.x_axis = glm::normalize(x - glm::dot(x, p.normal) * p.normal);
  if (a.status != b.status) p.status = ControllerStatus::not_converged;
  return p;
}

void ReadingFormer::resolve_waiting() {
  while (!waiting_.empty()) {
    const Settled& s = waiting_.front();
    const bool pose_after = !poses_.empty() && poses_.back().time >= s.time;
    if (!pose_after && !poses_ended_) return;  // the pose stream lags: wait for it
    std::string why = "the pose stream ended before it";
    auto pose = pose_after ? pose_at(s.time, &why) : std::nullopt;
    if (!pose) {
      note(s.time, "contact at " + seconds(s.time) + " dropped: " + why);
    } else {
      FormedReading r{s.time, s.sequence, {}};
      r.reading.position = pose->position;
      r.reading.normal = pose->normal;
      r.reading.x_axis = pose->x_axis;
      r.reading.pressure = s.pressure;
      r.reading.time_s = s.time;
      r.reading.status = pose->status.value_or(ControllerStatus::converged);
      readings_.push_back(std::move(r));
    }
    waiting_.pop_front();
  }
}

std::vector<FormedReading> ReadingFormer::take_readings() { return std::exchange(readings_, {}); }
std::vector<ContactNote> ReadingFormer::take_notes() { return std::exchange(notes_, {}); }

}  // namespace sva::drivers
