// _eval_trial: an evaluation trial as `sva eval` makes it (eval::TrialGenerator), for sva.trial_session.
#include <sva/dataset.hpp>
#include <sva/eval/trials.hpp>
#include <sva/map.hpp>

#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include "tools.hpp"

namespace sva::python {

using namespace nb::literals;

void bind_trials(nb::module_& m) {
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
