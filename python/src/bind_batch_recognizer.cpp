// sva.BatchRecognizer: many independent sessions against one map, stepped together (one backend call, one GPU
// submission, per add_readings). Calls take turns on one object; the GIL is released during them.
#include <sva/batch_file.hpp>
#include <sva/batch_recognizer.hpp>
#include <sva/engine.hpp>
#include <sva/error.hpp>

#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <mutex>
#include <string_view>

#include "bindings.hpp"
#include "recognizer_options.hpp"

namespace sva::python {

using namespace nb::literals;

namespace {

struct PyBatchRecognizer {
  PyBatchRecognizer(const Map& map, const PoseSpaceSpec& space, std::size_t sessions, const RecognizerOptions& o)
      : rec(map, space, sessions, o) {}
  BatchRecognizer rec;
  mutable std::mutex mutex;
};

void add_readings(PyBatchRecognizer& b, const std::vector<std::size_t>& sessions,
                  const std::vector<Reading>& readings) {
  if (sessions.size() != readings.size())
    throw Error("BatchRecognizer.add_readings: " + std::to_string(sessions.size()) + " sessions but " +
                std::to_string(readings.size()) + " readings (one reading per session)");
  EngineScope scope;
  std::lock_guard lock(b.mutex);
  b.rec.add_readings(sessions, readings);
}

// One shard of a sessions file, recognised on this batch (host/include/sva/batch_file.hpp).
nb::bytes recognize_shard(PyBatchRecognizer& b, const Map& map, nb::bytes text, const std::string& source,
                          std::size_t first_line, std::size_t first_session, std::size_t top_k,
                          const std::string& depth) {
  const EstimateDepth d = parse_estimate_depth(depth, "sva.recognize_batch: depth");
  std::string results;
  {
    const std::string_view lines(text.c_str(), text.size());
    EngineScope scope(true);
    std::lock_guard lock(b.mutex);
    results = recognize_batch_shard(b.rec, map, lines, source, first_line, first_session, top_k, d);
  }
  return nb::bytes(results.data(), results.size());
}

// One shard of a sessions file (`total` sessions) on up to `in_flight` recognizers of `engine`, `sessions` each, their
// groups in flight at once (sva.recognize_batch; host/include/sva/batch_file.hpp).
nb::bytes recognize_shard_in_flight(const Engine& engine, nb::bytes text, const std::string& source,
                                    std::size_t first_line, std::size_t first_session, std::size_t top_k,
                                    const std::string& depth, std::size_t total, std::size_t sessions,
                                    std::size_t in_flight, const nb::kwargs& options) {
  const EstimateDepth d = parse_estimate_depth(depth, "sva.recognize_batch: depth");
  const RecognizerOptions o = recognizer_options(options, "sva.recognize_batch");
  std::string results;
  {
    const std::string_view lines(text.c_str(), text.size());
    EngineScope scope(true);
    std::vector<BatchRecognizer> recs = batch_recognizers(engine, total, sessions, in_flight, o);
    results = recognize_batch_shard(recs, engine.map(), lines, source, first_line, first_session, top_k, d);
  }
  return nb::bytes(results.data(), results.size());
}

}  // namespace

void bind_batch_recognizer(nb::module_& m) {
  m.def("_recognize_shard_in_flight", &recognize_shard_in_flight, "engine"_a, "text"_a, "source"_a, "first_line"_a,
        "first_session"_a, "top_k"_a, "depth"_a, "total"_a, "sessions"_a, "in_flight"_a, "options"_a,
        "Result lines (bytes) of the sessions in `text` (as BatchRecognizer._recognize_shard), on `in_flight` "
        "recognizers of `engine` at once, `sessions` sessions each (sva.recognize_batch).");
  nb::class_<PyBatchRecognizer>(m, "BatchRecognizer",
                                "Many independent recognition sessions against one map, stepped together. Each "
                                "session's estimates equal those of a Recognizer fed the same readings.")
      .def(
          "__init__",
          [](PyBatchRecognizer* self, const Map& map, std::size_t sessions, const std::optional<PoseSpaceSpec>& space,
             const nb::kwargs& options) {
            const RecognizerOptions o = recognizer_options(options, "sva.BatchRecognizer");
            EngineScope scope;
            new (self) PyBatchRecognizer(map, space ? *space : map.pose_space(), sessions, o);
          },
          "map"_a, "sessions"_a, "pose_space"_a = nb::none(), "options"_a, nb::keep_alive<1, 2>(),
          nb::sig("def __init__(self, map: Map, sessions: int, pose_space: PoseSpaceSpec | None = None, "
                  "*, " RECOGNIZER_OPTIONS_SIG ") -> None"))
      .def("add_readings", &add_readings, "sessions"_a, "readings"_a,
           "Adds readings[i] to session sessions[i] (distinct sessions) in one update; on error nothing changes.")
      .def(
          "estimate",
          [](const PyBatchRecognizer& b, std::size_t session, std::size_t top_k, const std::string& depth) {
            const EstimateDepth d = parse_estimate_depth(depth, "BatchRecognizer.estimate: depth");
            EngineScope scope;
            std::lock_guard lock(b.mutex);
            return b.rec.estimate(session, top_k, d);
          },
          "session"_a, "top_k"_a = 5, "depth"_a = "full", "Recognizer.estimate, for one session.")
      .def(
          "estimates",
          [](const PyBatchRecognizer& b, const std::vector<std::size_t>& sessions, std::size_t top_k,
             const std::string& depth) {
            const EstimateDepth d = parse_estimate_depth(depth, "BatchRecognizer.estimates: depth");
            EngineScope scope;
            std::lock_guard lock(b.mutex);
            return b.rec.estimates(sessions, top_k, d);
          },
          "sessions"_a, "top_k"_a = 5, "depth"_a = "full",
          "The estimates of many sessions at once (the i-th is sessions[i]'s), each equal to estimate()'s: the "
          "sessions' fits run side by side on the recognizer's threads.")
      .def(
          "reset",
          [](PyBatchRecognizer& b, std::size_t session) {
            EngineScope scope;
            std::lock_guard lock(b.mutex);
            b.rec.reset(session);
          },
          "session"_a, "Forgets the session's readings and prior.")
      .def(
          "reset",
          [](PyBatchRecognizer& b, const std::vector<std::size_t>& sessions) {
            EngineScope scope;
            std::lock_guard lock(b.mutex);
            b.rec.reset(sessions);
          },
          "sessions"_a,
          "Forgets these sessions' readings and priors at once (a group's start): on a GPU their beliefs are emptied "
          "in one submission. Every id is checked before any session changes.")
      .def(
          "readings",
          [](const PyBatchRecognizer& b, std::size_t session) {
            std::lock_guard lock(b.mutex);
            return b.rec.readings(session);
          },
          "session"_a)
      .def(
          "belief_bytes",
          [](const PyBatchRecognizer& b, std::size_t session) {
            std::lock_guard lock(b.mutex);
            return b.rec.belief_bytes(session);
          },
          "session"_a,
          "Bytes the session's belief holds now (host memory on the CPU, device memory on Vulkan): most of a live "
          "session's memory; RecognizerOptions.belief_budget_bins bounds it.")
      .def("sessions", [](const PyBatchRecognizer& b) { return b.rec.sessions(); })
      .def_prop_ro(
          "backend", [](const PyBatchRecognizer& b) { return std::string(backend_name(b.rec.backend())); },
          "the backend in use: \"cpu\" or \"vulkan\" (auto resolved)")
      .def("backend_description", [](const PyBatchRecognizer& b) { return b.rec.backend_description(); })
      .def("backend_fallback_reason", [](const PyBatchRecognizer& b) { return b.rec.backend_fallback_reason(); })
      .def("_recognize_shard", &recognize_shard, "map"_a, "text"_a, "source"_a, "first_line"_a, "first_session"_a,
           "top_k"_a, "depth"_a = "full",
           "Result lines (bytes) of the sessions in `text`, whole lines of the sessions file `source` from line "
           "`first_line`, preceded by `first_session` sessions (sva.recognize_batch, sva.distributed).");
}

}  // namespace sva::python
