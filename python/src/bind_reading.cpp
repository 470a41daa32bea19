// sva.Reading: a pressure image and the sensor pose when it was taken. The image and vectors are NumPy views of the
// reading (float32 image, float64 vectors); assigning an array copies it in, after checking shape and dtype.
#include <sva/reading.hpp>

#include <nanobind/stl/string.h>

#include <algorithm>
#include <cstdio>

#include "bindings.hpp"

namespace sva::python {

using namespace nb::literals;

namespace {

// (rows, cols) when the reading knows its image's shape (a 2-D image was given, or its dataset's sensor), else flat.
nb::ndarray<nb::numpy, float> pressure_view(Reading& r) {
  if (r.rows > 0 && r.cols > 0 &&
      static_cast<std::size_t>(r.rows) * static_cast<std::size_t>(r.cols) == r.pressure.size())
    return nb::ndarray<nb::numpy, float>(
        r.pressure.data(), {static_cast<std::size_t>(r.rows), static_cast<std::size_t>(r.cols)}, nb::handle());
  return nb::ndarray<nb::numpy, float>(r.pressure.data(), {r.pressure.size()}, nb::handle());
}

// In place: NumPy views of the image stay valid, so its size is fixed, and so is its shape once known.
void set_pressure(Reading& r, nb::handle p) {
  auto image = to_pressure(p, "Reading.pressure");
  if (image.values.size() != r.pressure.size())
    throw nb::value_error(("Reading.pressure: the reading's image has " + std::to_string(r.pressure.size()) +
                           " values, the new one " + std::to_string(image.values.size()) +
                           "; make a new Reading for another sensor")
                              .c_str());
  if (image.rows != 0 && r.rows != 0 && (image.rows != r.rows || image.cols != r.cols))
    throw nb::value_error(("Reading.pressure: the reading's image is " + std::to_string(r.rows) + " x " +
                           std::to_string(r.cols) + ", the new one " + std::to_string(image.rows) + " x " +
                           std::to_string(image.cols) + "; make a new Reading for another sensor")
                              .c_str());
  std::copy(image.values.begin(), image.values.end(), r.pressure.begin());
  if (image.rows != 0) r.rows = image.rows, r.cols = image.cols;
}

void init_reading(Reading* r, nb::handle pressure, nb::handle position, nb::handle normal, nb::handle x_axis,
                  ControllerStatus status) {
  new (r) Reading();
  auto image = to_pressure(pressure, "Reading.pressure");
  r->pressure = std::move(image.values);
  r->rows = image.rows;
  r->cols = image.cols;
  r->position = to_vec3(position, "Reading.position");
  r->normal = to_vec3(normal, "Reading.normal");
  r->x_axis = to_vec3(x_axis, "Reading.x_axis");
  r->status = status;
}

}  // namespace

void bind_reading(nb::module_& m) {
  nb::enum_<ControllerStatus>(m, "ControllerStatus",
                              "How the contact controller ended; only converged readings are used.")
      .value("converged", ControllerStatus::converged)
      .value("not_converged", ControllerStatus::not_converged)
      .value("no_contact", ControllerStatus::no_contact);
  nb::class_<Reading>(m, "Reading",
                      "A tactile reading: the pressure image (kPa, row-major, rows along the sensor y axis) and the "
                      "sensor pose in the robot frame (position mm, outward surface normal, sensor x axis).")
      .def("__init__", &init_reading, "pressure"_a, "position"_a, "normal"_a,
           "x_axis"_a = nb::make_tuple(1.0, 0.0, 0.0), "status"_a = ControllerStatus::converged,
           nb::sig("def __init__(self, pressure: numpy.typing.ArrayLike, position: numpy.typing.ArrayLike, "
                   "normal: numpy.typing.ArrayLike, x_axis: numpy.typing.ArrayLike = (1.0, 0.0, 0.0), "
                   "status: ControllerStatus = ...) -> None"),
           "status defaults to ControllerStatus.converged.")
      .def_prop_rw(
          "pressure", &pressure_view, &set_pressure, nb::rv_policy::reference_internal,
          nb::for_setter(nb::sig("def pressure(self, arg: numpy.typing.ArrayLike, /) -> None")),
          "the pressure image, float32 kPa: (rows, cols) when the shape is known (a 2-D image was given, or the "
          "dataset's sensor), else flat (rows*cols,)")
      .def_ro("rows", &Reading::rows, "the image's rows when known (0: a flat image was given)")
      .def_ro("cols", &Reading::cols, "the image's columns when known (0: a flat image was given)")
      .def_prop_rw(
          "position", [](Reading& r) { return vec3_view(r.position); },
          [](Reading& r, nb::handle v) { r.position = to_vec3(v, "Reading.position"); },
          nb::rv_policy::reference_internal,
          nb::for_setter(nb::sig("def position(self, arg: numpy.typing.ArrayLike, /) -> None")), "sensor centre, mm")
      .def_prop_rw(
          "normal", [](Reading& r) { return vec3_view(r.normal); },
          [](Reading& r, nb::handle v) { r.normal = to_vec3(v, "Reading.normal"); }, nb::rv_policy::reference_internal,
          nb::for_setter(nb::sig("def normal(self, arg: numpy.typing.ArrayLike, /) -> None")),
          "outward surface normal the sensor was aligned to")
      .def_prop_rw(
          "x_axis", [](Reading& r) { return vec3_view(r.x_axis); },
          [](Reading& r, nb::handle v) { r.x_axis = to_vec3(v, "Reading.x_axis"); }, nb::rv_policy::reference_internal,
          nb::for_setter(nb::sig("def x_axis(self, arg: numpy.typing.ArrayLike, /) -> None")), "sensor x axis")
      .def_rw("status", &Reading::status)
      .def_ro("iterations", &Reading::iterations, "contact controller iterations used")
      .def_rw("time_s", &Reading::time_s,
              "when the contact settled, seconds on the clock of its frames (0: unknown, e.g. simulated)")
      .def("__copy__", [](const Reading& r) { return Reading(r); })
      .def("__repr__", [](const Reading& r) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "Reading(position=[%.2f, %.2f, %.2f], %zu pressure values, %s)", r.position.x,
                      r.position.y, r.position.z, r.pressure.size(), to_string(r.status));
        return std::string(buf);
      });
}

}  // namespace sva::python
