#pragma once
// Arguments that take an object or the path of its file (a Dataset or a .svad, a Map or a .svam), shared by the
// engine's module (sva.train) and the tools' module (sva.evaluate): one rule for both, one message for a bad one.
#include <sva/dataset.hpp>
#include <sva/map.hpp>

#include <memory>
#include <string>

#include "bindings.hpp"

namespace sva::python {

// A Dataset argument: a Dataset, or the path of a .svad file (loaded).
struct DatasetArg {
  const Dataset* data = nullptr;  // the caller's, or `loaded`
  std::shared_ptr<const Dataset> loaded;
  std::string name = "dataset";
};
DatasetArg dataset_arg(nb::handle obj, const char* what);

// A Map argument: a Map, or the path of a .svam file (loaded).
struct MapArg {
  Map map;
  std::string name = "map";
};
MapArg map_arg(nb::handle obj, const char* what);

}  // namespace sva::python
