// _write_preview: a dataset's preview (a PNG of its pressure images), as `sva simulate --preview` draws it, for
// sva.simulate(preview=...): the engine's module calls it after simulating.
#include <sva/dataset.hpp>
#include <sva/eval/dataset_export.hpp>

#include <nanobind/stl/filesystem.h>

#include <filesystem>

#include "tools.hpp"

namespace sva::python {

using namespace nb::literals;

void bind_preview(nb::module_& m) {
  m.def(
      "_write_preview",
      [](const Dataset& data, const std::filesystem::path& png) {
        EngineScope scope;
        io::write_preview(data, png);
      },
      "data"_a, "png"_a, "Writes the preview of `data`'s readings to `png`.");
}

}  // namespace sva::python
