#include "arguments.hpp"

#include <nanobind/stl/filesystem.h>

#include <filesystem>

namespace sva::python {

DatasetArg dataset_arg(nb::handle obj, const char* what) {
  DatasetArg a;
  if (nb::try_cast(obj, a.data, false) && a.data) return a;
  std::filesystem::path file;
  if (!nb::try_cast(obj, file))
    throw nb::type_error((std::string(what) + ": expected a Dataset or the path of a .svad file").c_str());
  {
    EngineScope scope(true);
    a.loaded = std::make_shared<const Dataset>(load_dataset(file));
  }
  a.data = a.loaded.get();
  a.name = file.string();
  return a;
}

MapArg map_arg(nb::handle obj, const char* what) {
  MapArg a;
  if (nb::try_cast(obj, a.map, false)) return a;
  std::filesystem::path file;
  if (!nb::try_cast(obj, file))
    throw nb::type_error((std::string(what) + ": expected a Map or the path of a .svam file").c_str());
  EngineScope scope(true);
  a.map = Map::load(file);
  a.name = file.string();
  return a;
}

}  // namespace sva::python
