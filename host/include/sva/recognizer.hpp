#pragma once
// The public recognition API: build a recognizer from a map and a pose space,
// feed it readings one at a time, read the estimate. This is what a robot
// perception stack includes.
#include <sva/map.hpp>
#include <sva/pose.hpp>
#include <sva/pose_space.hpp>
#include <sva/prior.hpp>
#include <sva/reading.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace sva {

// automatic ("auto"): Vulkan when a usable device exists, else the CPU
// reference; both give the same answers.
enum class BackendKind { cpu, vulkan, automatic };
// "cpu", "vulkan" or "auto"; anything else is an sva::Error naming `option` (e.g. "sva eval: --backend").
BackendKind parse_backend_kind(const std::string& text, const std::string& option);
// "cpu", "vulkan" or "auto".
const char* backend_kind_name(BackendKind kind);
enum class Method { sva, appearance };  // appearance: the appearance-only baseline of [15]

// How much of the estimate one call computes (docs/recognition.md, "Light and full estimates"):
//   full:  every stage the RecognizerOptions ask for: the fine pose and the surface check on the host.
//   light: the belief's answer alone (its objects, best bins, modes and parabolic pose; probabilities calibrated as
//          before the fine pose exists), no fit on the host: a robot's answer after every touch, with the full one
//          asked for when it must act on the fine pose or tell near-twins apart.
enum class EstimateDepth { full, light };
// "full" or "light"; anything else is an sva::Error naming `option` (e.g. "sva eval: --estimate").
EstimateDepth parse_estimate_depth(const std::string& text, const std::string& option);
// "full" or "light".
const char* estimate_depth_name(EstimateDepth depth);

struct RecognizerOptions {
  BackendKind backend = BackendKind::automatic;  // the policy of every command: a GPU where one is usable
  Method method = Method::sva;
  // Floor of every pair factor (DESIGN 4): factor = eps + S_p(x). See docs/recognition.md.
  double eps = 1e-6;
  // Speed knobs (defaults keep the paper's accuracy; docs/recognition.md):
  float likelihood_cutoff = 0.0f;         // skip matches whose Eq 15 likelihood (summed over shared keys) is below this
  double object_prune_probability = 0.0;  // skip map entries of objects whose posterior is below this
  int max_pairs_per_update = 0;           // 0 = all earlier readings (both orders); else the most recent ones
  unsigned threads = 0;                   // CPU backend's votes, every backend's estimate (fits, per-object modes):
                                          // 0 = all cores; results do not depend on it
  std::string vulkan_device;              // "" = prefer a discrete GPU (env SVA_VK_DEVICE)
  // The fine pose (docs/recognition.md): after the histogram, align the readings to the object's training
  // contacts (robust point-to-plane, on the host, the same for every backend). Off: the parabolic sub-bin pose.
  bool refine_pose = true;
  // The surface check (docs/recognition.md, "Surface check"): from 6 readings on (3 planar), the three leading
  // objects are each fitted to the readings and weighed by how well their surface explains every reading, which
  // tells near-twins apart (a shape at two scales, a mirror image). Costs up to two more fine poses per estimate.
  bool surface_check = true;
  // Bounded memory on long sessions (docs/recognition.md, "Bounded memory"): past this many touched pose bins a
  // session forgets the bins more than 256 bits of evidence below its best (never those the estimate reads).
  // 0 = no bound.
  std::size_t belief_budget_bins = std::size_t{1} << 22;
  // Distinct hypotheses (Estimate::hypotheses): bins within this many grid steps of a stronger mode of the same
  // object on every axis are the same hypothesis; a mode's mass and covariance sum the bins within it. 0 to 4.
  int hypothesis_radius_bins = 1;
  // Calibrated probabilities (docs/recognition.md, "Calibration"): temper each object's evidence by the map's
  // learned temperature, which falls with the reading count (Eq 5 counts each reading's evidence n-1 times), and
  // say how likely the object is none of the map's (Estimate::p_unknown). Off: Eq 5's product as it stands.
  bool calibrate = true;
  // The prior probability that a touched object is none of the map's, in (0, 1): p_unknown starts there and moves
  // with the evidence (maps that cannot say "none of these" keep it).
  double unknown_prior = 0.1;
};

struct Hypothesis {
  std::uint32_t object = 0;
  std::string object_name;
  RigidPose pose;            // pose of the object (x_world = R x_object + T)
  double probability = 0.0;  // posterior mass of this bin
};

// One distinct hypothesis: a mode of the belief. Maps onto vision_msgs/ObjectHypothesisWithPose (docs/api.md).
struct PoseHypothesis {
  std::uint32_t object = 0;
  std::string object_name;
  RigidPose pose;            // robot frame: the parabolic peak of the mode's best bin (for the best object's best
                             // mode, Estimate::pose: the fine pose when refined)
  double probability = 0.0;  // posterior mass of the mode: its bins within RecognizerOptions::hypothesis_radius_bins
  // Row-major 6 x 6, in the order of ROS geometry_msgs/PoseWithCovariance (x, y, z in mm; rotation about the
  // robot frame's X, Y, Z in radians, as a small rotation applied on the left of `pose.R`): the weighted second
  // moments of the mode's bins plus each bin's quantisation variance (width^2 / 12). Planar spaces: z and the
  // rotations about X and Y are fixed by the plane, so their rows and columns are 0.
  std::array<double, 36> covariance{};
  bool valid = false;  // false only in Estimate::object_hypotheses, for an object no vote has reached
};

// A hypothesis in ROS's units and conventions (geometry_msgs/PoseWithCovariance; docs/api.md, "Mapping an Estimate
// onto vision_msgs/Detection3D"): sva works in millimetres and rotation matrices, a robot stack in metres and
// quaternions.
struct RosPose {
  std::array<double, 3> position{};                       // metres
  std::array<double, 4> orientation{0.0, 0.0, 0.0, 1.0};  // unit quaternion x, y, z, w (w >= 0)
  std::array<double, 36> covariance{};                    // row-major: x, y, z (m), rotation about X, Y, Z (rad)
};
RosPose to_ros(const PoseHypothesis& hypothesis);

// What the posterior over objects is made of (docs/recognition.md, "What the posterior is made of"), per object id:
// object_probability is proportional to 2^(temperature x pairs_log2_mass + surface_weight x surface_log2_fit) times
// the prior, then the calibration's top label reshapes the leading object's share. For studies that weigh the
// evidence otherwise (`sva eval --evidence`); a robot needs only object_probability.
struct ObjectEvidence {
  std::vector<double> pairs_log2_mass;   // the pairs' votes (Eq 5): log2 of the object's mass over poses, relative to
                                         // the belief's best bin (empty before the first reading)
  std::vector<double> surface_log2_fit;  // the surface check's bits: how well each leading object's surface explains
                                         // the readings, the others at the worst of theirs (empty when it did not run)
  double temperature = 1.0;              // the calibration's at this reading count (1 without one)
  double surface_weight = 0.0;           // the calibration's learned weight of surface_log2_fit
};

struct Estimate {
  // false before the session's first reading: there is no answer yet. object_probability is then the prior
  // (uniform without one); object_name is empty, the poses are the identity, top and the hypotheses are empty.
  bool ready = false;
  std::size_t readings = 0;  // readings seen so far
  std::uint32_t object = 0;  // the object with the most mass summed over poses
  std::string object_name;
  std::vector<double> object_probability;  // per object, sums to 1: the posterior given that the object is one of
                                           // the map's (calibrated unless RecognizerOptions::calibrate is off)
  // The probability that the touched object is none of the map's objects (docs/recognition.md, "None of these"):
  // the probability of object o is then (1 - p_unknown) object_probability[o]. The prior before the second reading
  // and on maps that cannot say it; 0 with calibration off.
  double p_unknown = 0.0;
  ObjectEvidence evidence;                 // what object_probability is made of (empty parts before the first reading)
  RigidPose pose;                          // continuous pose of `object`: the fine pose when refined, else
                                           // `parabolic_pose`
  RigidPose parabolic_pose;                // the histogram's: parabolic peak of the log-belief at the best bin
  RigidPose bin_pose;                      // centre of its best bin
  bool pose_refined = false;               // `pose` is aligned to the surface (RecognizerOptions::refine_pose
                                           // on, enough readings, a better fit than the histogram's pose)
  bool pose_valid = false;                 // false until a pair has voted (and for Method::appearance)
  std::vector<Hypothesis> top;             // best bins, most probable first (neighbouring bins of one mode: see
                                           // `hypotheses` for distinct ones)
  std::vector<PoseHypothesis> hypotheses;  // distinct modes over all objects (non-maximum suppression), strongest
                                           // peak first, at most estimate()'s top_k
  std::vector<PoseHypothesis> object_hypotheses;  // per object id: its best mode (empty for Method::appearance)
  std::uint64_t votes = 0;                        // votes cast by the last update
  std::uint64_t votes_outside = 0;                // votes of the last update whose pose fell outside the pose space
                                                  // (many: the space may not contain the object's pose)
  std::uint64_t votes_zero = 0;                   // of `votes`, those whose fixed-point mass (2^-24 units, rounded to
                                                  // nearest) is 0: counted, they add nothing to the belief (many: the
                                                  // likelihoods are tiny, e.g. a likelihood_cutoff of 0 on a large map)
};

class Engine;  // sva/engine.hpp

// One recognition session. Thread safety: every call (const ones included) takes the recognizer's lock, so one
// recognizer may be used from several threads, one call at a time; recognizers of one Engine run at once.
class Recognizer {
 public:
  // A recognizer with its own engine on `options.backend` (the map uploaded for it alone, unless another
  // recognizer of the process already holds the same map on the same device).
  Recognizer(const Map& map, const PoseSpaceSpec& pose_space, const RecognizerOptions& options = {});
  // A recognizer sharing `engine` (its map, backend and device: options.backend and vulkan_device are the
  // engine's). The engine's state is kept alive by the recognizer.
  Recognizer(const Engine& engine, const PoseSpaceSpec& pose_space, const RecognizerOptions& options = {});
  ~Recognizer();
  Recognizer(Recognizer&&) noexcept;
  Recognizer& operator=(Recognizer&&) noexcept;

  // Adds one reading (robot frame) and updates the belief with its pairs with
  // every earlier reading, in both orders (Eq 3-5). Readings that are not
  // `converged` or that cannot be described are refused with sva::Error.
  void add_reading(const Reading& reading);
  // top_k: the best bins (Estimate::top) and the distinct hypotheses (Estimate::hypotheses) to report; depth: the
  // whole estimate, or the belief's answer without the host's fits (EstimateDepth). Either leaves the session as it
  // was: a full estimate after a light one equals a full estimate alone.
  Estimate estimate(std::size_t top_k = 5, EstimateDepth depth = EstimateDepth::full) const;
  // A prior over objects for this session (sva/prior.hpp), replacing any earlier one; sva::Error when it does not
  // fit the map. It may be set or changed at any time: it enters at estimate time.
  void set_prior(const Prior& prior);
  // Forgets the readings and the prior: a fresh session (the belief's and the backend's memory is kept).
  void reset();
  // Saves the session (its readings so far, as given, and its prior) to a small versioned file, so that a robot
  // can resume; restore_session replaces this session by the saved one, whose belief it rebuilds bit for bit by
  // replaying the readings. sva::Error naming the file when it cannot be read or was saved with another map.
  void save_session(const std::filesystem::path& file) const;
  void restore_session(const std::filesystem::path& file);
  // How many readings the session holds (0 after reset(); the estimate is not ready until there is one).
  std::size_t reading_count() const;
  [[deprecated("use reading_count()")]] std::size_t readings() const { return reading_count(); }

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace sva
