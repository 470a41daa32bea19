// sva._read_sessions: a sessions file (docs/batch-format.md) read by the engine's own reader, so that Python tools
// (sva.read_sessions, sva.ros) accept and refuse exactly what `sva recognize` does, with its FILE:LINE messages.
// sva._eval_trial: an evaluation trial as `sva eval` makes it (eval::TrialGenerator), for sva.trial_session.
#include <sva/dataset.hpp>
#include <sva/eval/batch_sessions.hpp>
#include <sva/eval/trials.hpp>
#include <sva/map.hpp>

#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include "bindings.hpp"

namespace sva::python {

using namespace nb::literals;

void bind_sessions(nb::module_& m) {
  m.def(
      "_read_sessions",
      [](const std::string& file, int elements) {
        std::vector<std::tuple<std::string, std::vector<Reading>, std::string>> out;
        std::vector<io::BatchSession> sessions;
        {
          nb::gil_scoped_release release;
          sessions = io::read_batch_sessions(file, elements);
        }
        for (auto& s : sessions)
          out.emplace_back(s.id, std::move(s.readings), s.truth.is_null() ? std::string() : s.truth.dump());
        return out;
      },
      "file"_a, "elements"_a,
      "(id, readings, truth as JSON text or \"\") per session of a sessions file whose pressure images have "
      "`elements` values; sva.Error names the line and the field of a bad one.");
  m.def(
      "_eval_trial",
      [](const Dataset& test, const Map& map, std::size_t trial, std::uint64_t seed, std::size_t max_readings,
         const std::string& source) {
        nb::gil_scoped_release release;
        const eval::TrialGenerator generator(test, map.pose_space(), seed, max_readings, source);
        eval::Trial t = generator.make(trial);
        return std::make_tuple(std::move(t.readings), test.scene.objects[t.object].name, t.pose);
      },
      "test"_a, "map"_a, "trial"_a, "seed"_a, "max_readings"_a, "source"_a,
      "(readings, object name, true pose) of evaluation trial `trial` as sva eval makes it with this seed and "
      "max_readings.");
}

}  // namespace sva::python
