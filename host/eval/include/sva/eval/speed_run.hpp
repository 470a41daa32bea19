#pragma once
// The timed runs of `sva bench`: trials through one backend in lock step
// (recognition/lockstep.hpp), `sessions` per update (one GPU submission with
// Vulkan, one CPU reference call otherwise), with the time per update, votes
// and session-updates per second, zero-mass votes, host and device memory, and
// the accuracy and error those updates buy at chosen reading counts.
#include <sva/dataset.hpp>
#include <sva/map.hpp>
#include <sva/recognizer.hpp>

#include <cstddef>
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include <sva/eval/process_memory.hpp>

namespace sva::bench {

// A camera's detection for every session (`sva bench --pose-prior`): a Gaussian pose prior (sva/prior.hpp) at the
// trial's true pose, the same for every object of the map (a camera that sees where the object is, not which one),
// over the position and, with rotation_sigma_deg > 0, the rotation. position_sigma_mm 0: no prior.
struct BenchPosePrior {
  double position_sigma_mm = 0.0;
  double rotation_sigma_deg = 0.0;
  bool on() const { return position_sigma_mm > 0.0; }
};

struct SpeedRunSpec {
  BackendKind backend = BackendKind::cpu;  // cpu or vulkan (never automatic: a report names what ran)
  std::size_t trials = 1;
  std::size_t sessions = 1;              // per update; 1 measures the single-session latency
  std::vector<std::size_t> checkpoints;  // reading counts to report, increasing
  std::uint64_t seed = 1;
  std::string label;          // progress text
  std::string vulkan_device;  // "" = the default choice
  bool refine_pose = true;    // RecognizerOptions::refine_pose (its cost shows in estimate_ms)
  // RecognizerOptions::surface_check. Off, with refine_pose off, the host fits only the best object after every
  // update (and only where the map's calibration says "none of these", from that fit): what a batch study that
  // checks surfaces only at its sessions' ends pays.
  bool surface_check = true;
  // The estimate after every update: full, or light (the belief's answer alone, no host fit: what a robot's answer
  // after every touch, or a batch that fits only at its sessions' ends, pays per update).
  EstimateDepth estimate = EstimateDepth::full;
  int max_pairs_per_update = 0;    // RecognizerOptions::max_pairs_per_update (0: the exact filter)
  float likelihood_cutoff = 0.0f;  // RecognizerOptions::likelihood_cutoff (0: every match votes)
  std::size_t belief_budget_bins = RecognizerOptions{}.belief_budget_bins;  // RecognizerOptions::belief_budget_bins
  // Hypotheses per estimate after every update. 1 measures what the GPU runs so far measured; sva recognize's
  // default, 3, takes the estimate's modes (the device's key choice ranks its selection: belief_hoods.comp's RANK).
  std::size_t top_k = 1;
  BenchPosePrior pose_prior;  // each session's, set after its batch slot is reset
  // First step one group of `sessions` trials to the last reading count, untimed: a reset session keeps its tables, so
  // the timed run's start at the size its sessions reach, as in a long study's later groups (and in the one-session
  // run after its first trial). Off, a batched run whose trials fill one group grows every session's tables.
  bool warm = false;
};

// One run, as the JSON report gives it (docs/evaluation.md, "sva bench").
// `meter` measures the run's host memory from before its backend is made to
// its end, with the backend still alive.
nlohmann::json run_speed(const Map& map, const Dataset& test, const SpeedRunSpec& spec, MemoryMeter& meter);

// The bare-scatter roofline of the device (roofline/roofline.hpp), as the JSON report gives it.
nlohmann::json roofline_json(std::size_t votes, std::size_t bins, const std::string& device);

// What `sva bench` runs: the backends, and per backend one session and (batch > 1) a batch of sessions per update.
struct BenchPlan {
  std::vector<BackendKind> backends;
  std::size_t trials = 3, batch = 64, roofline_votes = 1 << 22;
  std::vector<std::size_t> checkpoints;
  std::uint64_t seed = 1;
  std::string device;
  bool refine_pose = true;
  bool surface_check = true;
  EstimateDepth estimate = EstimateDepth::full;
  int max_pairs_per_update = 0;
  float likelihood_cutoff = 0.0f;
  std::size_t belief_budget_bins = RecognizerOptions{}.belief_budget_bins;
  std::size_t top_k = 1;  // SpeedRunSpec::top_k
  BenchPosePrior pose_prior;
  bool warm = false;  // SpeedRunSpec::warm
};

// The whole report of `sva bench` (docs/evaluation.md, "sva bench"): the scene, the map's size and the threads;
// every run of the plan, each non-CPU run with its speed-up over the CPU reference's single session
// (speedup_vs_cpu) and over the CPU batch of the same size (speedup_vs_cpu_batch) per reading count; the
// roofline and each Vulkan run's fraction of it when Vulkan runs; the process's peak RSS.
nlohmann::json run_bench(const Map& map, const Dataset& test, const BenchPlan& plan);

}  // namespace sva::bench
