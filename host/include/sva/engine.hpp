#pragma once
// An engine: the map, the backend chosen once for it (auto resolved here), and
// what every recognition session on that map can share: on Vulkan the device,
// its pipelines and one uploaded copy of the map; on every backend the host
// map and the fine pose's surface index. Any number of Recognizers and
// BatchRecognizers made from one Engine share them, so N sessions hold one
// map's memory (docs/api.md, "Engines and sessions").
//
// Thread safety: an Engine is an immutable, cheap-to-copy handle; recognizers
// made from it may be used from different threads at once (their GPU work
// takes turns on the device's one queue). Each Recognizer and BatchRecognizer
// serialises its own calls with a lock, so one may also be shared between
// threads, at the cost of waiting.
#include <sva/map.hpp>
#include <sva/recognizer.hpp>

#include <memory>
#include <string>

namespace sva {

struct EngineOptions {
  BackendKind backend = BackendKind::automatic;  // auto: a GPU where one is usable, else the CPU reference
  std::string vulkan_device;                     // "" = prefer a discrete GPU (env SVA_VK_DEVICE)
};

class Engine {
 public:
  // Chooses the backend and, on Vulkan, uploads the map. sva::Error when the map is empty or the asked-for
  // backend cannot be made (auto then falls back to the CPU reference instead, with the reason).
  explicit Engine(const Map& map, const EngineOptions& options = {});

  const Map& map() const;
  // cpu or vulkan (auto resolved).
  BackendKind backend() const;
  // With auto on the CPU: why no Vulkan device was usable ("" otherwise).
  const std::string& fallback_reason() const;
  // "cpu", or "vulkan: DEVICE".
  std::string backend_description() const;
  // The sessions a BatchRecognizer on this engine steps together by default (`sva recognize`,
  // `sva.recognize_batch`). On a GPU: as many as half of its memory left by the map holds with every session's
  // belief at its bound (`options.belief_budget_bins`), shared by the submissions in flight, from 64 to 4096 each;
  // on the CPU reference, lavapipe, or without a bound: 64 (the CPU's workers are busy from a few sessions on).
  std::size_t sessions_per_submission(const RecognizerOptions& options = {}) const;
  // The recognizers whose groups a batch keeps in flight at once by default (BatchSessionsFile::recognize): two on a
  // GPU, so that the host prepares one group's update while the device runs the other's; one on a CPU (the
  // reference or lavapipe), whose cores the one already fills.
  std::size_t submissions_in_flight() const;

  struct Impl;

 private:
  // The recognizers reach the shared state through sva's private EngineAccess; users get no handle on it.
  friend struct EngineAccess;
  std::shared_ptr<Impl> impl_;
};

}  // namespace sva
