// sva._read_sessions: a sessions file (docs/batch-format.md) read by the engine's own reader, so that Python tools
// (sva.read_sessions, sva.ros) accept and refuse exactly what `sva recognize` does, with its FILE:LINE messages.
#include <sva/batch_file.hpp>

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
        std::vector<BatchSession> sessions;
        {
          nb::gil_scoped_release release;
          sessions = read_batch_sessions(file, elements);
        }
        for (auto& s : sessions) out.emplace_back(s.id, std::move(s.readings), s.truth);
        return out;
      },
      "file"_a, "elements"_a,
      "(id, readings, truth as JSON text or \"\") per session of a sessions file whose pressure images have "
      "`elements` values; sva.Error names the line and the field of a bad one.");
}

}  // namespace sva::python
