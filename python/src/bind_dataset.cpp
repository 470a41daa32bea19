// sva.Dataset and sva.Sample: readings of a scene's objects with ground truth (docs/dataset-format.md). Samples are
// views into the dataset; the array accessors stack every sample's values into one NumPy array.
#include <sva/dataset.hpp>
#include <sva/error.hpp>

#include <nanobind/make_iterator.h>
#include <nanobind/stl/filesystem.h>
#include <nanobind/stl/string.h>

#include <cstring>

#include "bindings.hpp"

namespace sva::python {

using namespace nb::literals;

namespace {

template <class T>
nb::ndarray<nb::numpy, T> owned_array(std::vector<T>&& values, std::initializer_list<std::size_t> shape) {
  auto* v = new std::vector<T>(std::move(values));
  nb::capsule owner(v, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
  return nb::ndarray<nb::numpy, T>(v->data(), shape, owner);
}

// Every sample's image as (samples, rows, cols) float32; images of another size are an sva.Error.
nb::ndarray<nb::numpy, float> pressures(const Dataset& d) {
  const SensorSpec& s = d.scene.sensor;
  const auto n = static_cast<std::size_t>(s.elements());
  std::vector<float> out(d.samples.size() * n);
  for (std::size_t i = 0; i < d.samples.size(); ++i) {
    const auto& p = d.samples[i].reading.pressure;
    if (p.size() != n)
      throw Error("dataset sample " + std::to_string(i) + ": " + std::to_string(p.size()) +
                  " pressure values, the scene's sensor has " + std::to_string(n));
    std::memcpy(out.data() + i * n, p.data(), n * sizeof(float));
  }
  return owned_array(std::move(out),
                     {d.samples.size(), static_cast<std::size_t>(s.rows), static_cast<std::size_t>(s.cols)});
}

// One vector of every sample's reading as (samples, 3) float64.
nb::ndarray<nb::numpy, double> vectors(const Dataset& d, glm::dvec3 Reading::*field) {
  std::vector<double> out;
  out.reserve(d.samples.size() * 3);
  for (const auto& s : d.samples)
    for (int k = 0; k < 3; ++k) out.push_back((s.reading.*field)[k]);
  return owned_array(std::move(out), {d.samples.size(), 3});
}

Sample& sample_at(Dataset& d, long long i) {
  const auto n = static_cast<long long>(d.samples.size());
  if (i < 0) i += n;
  if (i < 0 || i >= n)
    throw nb::index_error(("dataset sample index out of range (" + std::to_string(n) + " samples)").c_str());
  return d.samples[static_cast<std::size_t>(i)];
}

}  // namespace

void bind_dataset(nb::module_& m) {
  nb::class_<Sample>(m, "Sample", "One reading of a dataset with its ground truth.")
      .def_rw("reading", &Sample::reading)
      .def_rw("object_pose", &Sample::object_pose, "true pose of the object when the reading was taken")
      .def_prop_ro(
          "object", [](const Sample& s) { return s.object; }, "true object id (index into the scene's objects)")
      .def_prop_ro(
          "converged", [](const Sample& s) { return s.reading.status == ControllerStatus::converged; },
          "whether the contact controller converged: only such readings are used (add_reading refuses others)");
  nb::class_<Dataset>(m, "Dataset", "Readings of a scene's objects with ground truth (a .svad file).")
      .def(nb::init<>())
      .def_static(
          "load",
          [](const std::filesystem::path& file) {
            EngineScope scope(true);
            return load_dataset(file);
          },
          "path"_a, "Load a .svad file (sva simulate).")
      .def(
          "save",
          [](const Dataset& d, const std::filesystem::path& file) {
            EngineScope scope(true);
            save_dataset(d, file);
          },
          "path"_a)
      .def_rw("scene", &Dataset::scene)
      .def_rw("split", &Dataset::split)
      .def_rw("seed", &Dataset::seed)
      .def("count_converged", &Dataset::count_converged)
      .def("__len__", [](const Dataset& d) { return d.samples.size(); })
      .def("__getitem__", &sample_at, nb::rv_policy::reference_internal)
      .def(
          "__iter__",
          [](Dataset& d) {
            return nb::make_iterator(nb::type<Dataset>(), "SampleIterator", d.samples.begin(), d.samples.end());
          },
          nb::keep_alive<0, 1>())
      .def("pressures", &pressures, "Every sample's pressure image, (samples, rows, cols) float32 kPa (a copy).")
      .def(
          "positions", [](const Dataset& d) { return vectors(d, &Reading::position); },
          "Every sample's sensor position, (samples, 3) mm (a copy).")
      .def(
          "normals", [](const Dataset& d) { return vectors(d, &Reading::normal); },
          "Every sample's surface normal, (samples, 3) (a copy).")
      .def(
          "objects",
          [](const Dataset& d) {
            std::vector<std::uint32_t> out;
            for (const auto& s : d.samples) out.push_back(s.object);
            return owned_array(std::move(out), {d.samples.size()});
          },
          "Every sample's true object id, (samples,) uint32 (a copy).")
      .def(
          "converged",
          [](const Dataset& d) {
            std::vector<std::uint8_t> out;
            for (const auto& s : d.samples) out.push_back(s.reading.status == ControllerStatus::converged);
            auto a = owned_array(std::move(out), {d.samples.size()});
            return nb::module_::import_("numpy").attr("asarray")(a, "dtype"_a = "bool");
          },
          nb::sig("def converged(self) -> numpy.typing.NDArray[numpy.bool_]"),
          "Which samples the contact controller converged on, (samples,) bool.")
      .def("__repr__", [](const Dataset& d) {
        return "Dataset(scene='" + d.scene.name + "', split='" + d.split + "', " + std::to_string(d.samples.size()) +
               " samples)";
      });
}

}  // namespace sva::python
