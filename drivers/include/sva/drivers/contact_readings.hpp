#pragma once
// From frames and the arm's poses to readings. The arm reports timestamped
// poses (JSON lines); a contact is settled when consecutive frames agree (the
// settle rule below); the reading is the last settled frame's pressure image
// with the sensor pose interpolated at that frame's time. This gives hardware
// readings the meaning of a simulated converged reading: the pressure image
// once the contact controller has reached its target. Rule and formats:
// docs/usb-sensor.md.
#include <sva/drivers/calibration.hpp>
#include <sva/drivers/frame.hpp>
#include <sva/reading.hpp>

#include <deque>
#include <optional>
#include <string>
#include <vector>

namespace sva::drivers {

struct PoseSample {
  double time = 0;  // seconds, on the frames' clock (monotonic_ns / 1e9)
  glm::dvec3 position{0.0}, normal{0, 0, 1}, x_axis{1, 0, 0};
  std::optional<ControllerStatus> status;  // the arm controller's own verdict, when it gives one
};

// One JSON line: {"time": s, "position": [x,y,z], "normal": [...], "x_axis": [...], "status": "converged"}.
// Throws sva::Error naming `source` and the fault.
PoseSample parse_pose_line(const std::string& line, const std::string& source);
std::string pose_line(const PoseSample& pose);

// The settle rule: `frames` consecutive frames (no sequence gap between them)
// whose mean pressure is within `tolerance_kpa` of `target_kpa` (target 0: any
// mean above `contact_kpa`) and whose every element changes by at most
// `stable_kpa` between consecutive frames; none may be saturated. One reading
// per contact: the mean must fall below `contact_kpa` (release) before the
// next contact can settle.
struct SettleRule {
  int frames = 5;
  double target_kpa = 0.0;
  double tolerance_kpa = 5.0;
  double stable_kpa = 1.0;
  double contact_kpa = 0.5;
  double max_pose_gap_s = 0.5;  // poses further apart than this around a contact are not interpolated
  // Added to every pose's time before frames are matched to poses: for an arm whose clock is not the host's
  // monotonic clock (pose time + offset = host time). Poses are recorded as they came; the offset is saved with
  // the rule, so a replay matches them the same way.
  double pose_clock_offset_s = 0.0;
  void validate() const;  // throws sva::Error naming the bad value
  std::string to_json() const;
  static SettleRule from_json(const std::string& text, const std::string& source);
};

// What became of a settled contact, or of a frame stream event worth recording.
struct FormedReading {
  double time = 0;  // the last settled frame's time, s
  std::uint16_t sequence = 0;
  Reading reading;
};

struct ContactNote {
  double time = 0;
  std::string text;  // e.g. "contact at 1.23 s dropped: the pose stream ended before it"
};

class ReadingFormer {
 public:
  ReadingFormer(Calibration calibration, SettleRule rule);
  // Feed in time order. A frame that settles a contact leaves it pending until
  // a pose at or after its time has arrived (the pose stream may lag).
  void add_frame(const StreamFrame& frame);
  void add_pose(const PoseSample& pose);  // throws on a pose older than the previous one (its time as given, before
                                          // SettleRule::pose_clock_offset_s is added)
  void link_lost(double time);            // a disconnect breaks any contact in progress
  void poses_ended();                     // no more poses: pending contacts are dropped with a note
  // Readings and notes ready so far (moved out).
  std::vector<FormedReading> take_readings();
  std::vector<ContactNote> take_notes();
  std::size_t pending() const { return waiting_.size(); }

 private:
  struct Settled {
    double time;
    std::uint16_t sequence;
    std::vector<float> pressure;
  };
  void note(double time, std::string text);
  void resolve_waiting();
  std::optional<PoseSample> pose_at(double time, std::string* why) const;
  Calibration calibration_;
  SettleRule rule_;
  std::deque<std::vector<float>> window_;
  bool in_contact_ = false, settled_ = false;
  std::deque<PoseSample> poses_;
  bool poses_ended_ = false;
  std::deque<Settled> waiting_;
  std::vector<FormedReading> readings_;
  std::vector<ContactNote> notes_;
};

}  // namespace sva::drivers
