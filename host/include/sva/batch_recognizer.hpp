#pragma once
// Batch recognition: many independent recognition sessions against one map,
// stepped together so that one backend call (one GPU submission with the
// Vulkan backend) carries the pairs of every session that got a new reading.
// Each session's results equal those of a Recognizer fed the same readings.
// Thread safety: every call (const ones included: with the Vulkan backend even
// estimate() runs GPU work) takes the recognizer's lock, so calls from several
// threads run one at a time; batch recognizers of one Engine run at once.
#include <sva/recognizer.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace sva {

class BatchRecognizer {
 public:
  BatchRecognizer(const Map& map, const PoseSpaceSpec& pose_space, std::size_t sessions,
                  const RecognizerOptions& options = {});
  // Sessions sharing `engine` (Recognizer's constructor from an Engine).
  BatchRecognizer(const Engine& engine, const PoseSpaceSpec& pose_space, std::size_t sessions,
                  const RecognizerOptions& options = {});
  ~BatchRecognizer();
  BatchRecognizer(BatchRecognizer&&) noexcept;
  BatchRecognizer& operator=(BatchRecognizer&&) noexcept;

  std::size_t sessions() const;
  // Adds readings[i] to session sessions[i] (distinct sessions), all in one
  // update. Every reading is checked before any session changes: on error
  // (sva::Error naming the session and reading) nothing is updated.
  void add_readings(std::span<const std::size_t> sessions, std::span<const Reading> readings);
  // Recognizer::estimate, for one session.
  Estimate estimate(std::size_t session, std::size_t top_k = 5, EstimateDepth depth = EstimateDepth::full) const;
  // The estimates of many sessions at once (sessions[i]'s is the i-th), each equal to estimate()'s: the sessions'
  // fits run side by side on RecognizerOptions::threads workers (a batch's estimate after every update; with the
  // Vulkan backend the belief is read one session at a time, then the fits run on the host's cores).
  std::vector<Estimate> estimates(std::span<const std::size_t> sessions, std::size_t top_k = 5,
                                  EstimateDepth depth = EstimateDepth::full) const;
  // Recognizer::set_prior, for one session.
  void set_prior(std::size_t session, const Prior& prior);
  // Forgets the session's readings and prior.
  void reset(std::size_t session);
  // The same for many sessions at once (a group's start): on a GPU their beliefs are emptied in one submission.
  void reset(std::span<const std::size_t> sessions);
  // Recognizer::save_session and restore_session, for one session.
  void save_session(std::size_t session, const std::filesystem::path& file) const;
  void restore_session(std::size_t session, const std::filesystem::path& file);
  std::size_t readings(std::size_t session) const;
  // Bytes the session's belief holds now (host memory on the CPU, device memory on Vulkan; 0 for the appearance
  // method): most of a live session's memory. RecognizerOptions::belief_budget_bins bounds it (docs/recognition.md,
  // "Bounded memory").
  std::uint64_t belief_bytes(std::size_t session) const;
  // The backend in use ("cpu" or "vulkan") and, for Vulkan, the device.
  std::string backend_description() const;
  // The backend in use: cpu or vulkan (BackendKind::automatic has been resolved).
  BackendKind backend() const;
  // With BackendKind::automatic on the CPU: why no Vulkan device was usable ("" otherwise).
  std::string backend_fallback_reason() const;
  // One kernel's share of an update's device time: its GPU ms and its dispatches.
  struct KernelTime {
    double ms = 0.0;
    std::uint64_t dispatches = 0;
  };
  // Where the last update's vote time went (Vulkan: GPU kernel time and the
  // backend's host-side preparation and read-back; CPU: all host).
  struct Timing {
    double kernel_ms = 0.0;
    double host_ms = 0.0;
    double fold_ms = 0.0;  // of kernel_ms: the fold into the beliefs
    // Of host_ms: growing the sessions' belief tables (Vulkan: a new device buffer and its submissions per session
    // that grows; 0 on the CPU, whose growth is part of the fold).
    double belief_growth_ms = 0.0;
    // Where a device's host_ms went (0 on the CPU): recording its submissions, waiting for them (the device's span
    // from each one's first command to its last, device_span_ms, and the latency around it), and the rest outside
    // them. kernel_ms + host_ms = record_ms + wait_ms + the time outside the submissions.
    double record_ms = 0.0;
    double wait_ms = 0.0;
    double device_span_ms = 0.0;  // 0 where the device has no timestamps
    // The device's time by kernel, per pipeline named by its shader ("match_votes", ...), and the passes of one that
    // runs several apart ("belief_fold:add", "belief_reduce:mass", ...): which kernels kernel_ms is, summed over the
    // names. Empty on the CPU, where the device has no timestamps, and with SVA_VK_TIMESTAMPS=0.
    std::map<std::string, KernelTime> kernel_ms_by_pipeline;
  };
  Timing last_backend_timing() const;
  // Where the last estimates()'s time went, in ms summed over its sessions (run side by side, so the sum can exceed
  // the call's time): reading the belief (the estimate's stage 1, with a device's reads ahead), the fine poses, the
  // surface check, and the calibrated posterior with the report (docs/architecture.md, the estimate's stages 1-5).
  struct EstimateTiming {
    std::size_t sessions = 0;  // that ran the stages (a session without readings does not)
    double belief_ms = 0.0;
    double fit_ms = 0.0;
    double verify_ms = 0.0;
    double posterior_ms = 0.0;
    // Under a util::SpanProbe (sva/base/parallel.hpp) on the calling thread, each stage's span (critical path) as its
    // loops split for the recognizer's threads, summed likewise; 0 without one. Which stage bounds a many-core host.
    double belief_span_ms = 0.0, fit_span_ms = 0.0, verify_span_ms = 0.0, posterior_span_ms = 0.0;
  };
  EstimateTiming last_estimate_timing() const;
  // Device submissions so far (each a round trip to the device: submit, then wait), the estimates' reads of the
  // beliefs included: what `sva bench` divides by the estimates made. With an Engine shared by recognizers, of
  // every recognizer on its device. 0 on the CPU.
  std::uint64_t device_submissions() const;
  // Device memory allocations so far (on a GPU each a call into its driver: a block that many buffers share, or a
  // large buffer's own), counted likewise; 0 on the CPU.
  std::uint64_t device_allocations() const;
  // What the last update did, summed over its sessions' pairs (`sva bench` reports it per stage; docs/recognition.md,
  // "Work counted"). The CPU reference counts all but the atomics; the Vulkan backend all but the belief probes
  // (0 where not counted).
  struct Work {
    std::uint64_t pairs = 0;          // observed pairs voted (one order of each; the fold counts it twice)
    std::uint64_t entries = 0;        // map entries under the pairs' keys (read to find the matches)
    std::uint64_t matches = 0;        // map pairs aligned
    std::uint64_t votes = 0;          // beta samples inside the pose space
    std::uint64_t table_probes = 0;   // slots probed in the pairs' vote tables
    std::uint64_t bins = 0;           // pose bins the pairs voted for (the fold terms)
    std::uint64_t belief_probes = 0;  // slots probed in the sessions' beliefs to add the terms
    std::uint64_t atomics = 0;        // device atomics on the vote tables: key compare-and-swaps and adds
  };
  Work last_update_work() const;
  // Device memory the backend holds (Vulkan: map, vote table, beliefs). 0 on the CPU, and 0 where the
  // backend does not report it.
  struct DeviceMemory {
    std::uint64_t bytes = 0;
    std::uint64_t map_bytes = 0;  // of `bytes`, the uploaded map's
    // What the device's memory allocations hold: `bytes` and the free ranges of the blocks that buffers share
    // (with host-visible memory the device maps, where `bytes` counts the device's own memory alone).
    std::uint64_t held_bytes = 0;
  };
  DeviceMemory device_memory() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace sva
