// NumPy conversions and the engine scope shared by the bindings (bindings.hpp).
#include <sva/base/interrupt.hpp>
#include <sva/error.hpp>
#include <sva/recognizer.hpp>

#include <algorithm>
#include <string>

#include <nanobind/stl/string.h>

#include "bindings.hpp"

namespace sva::python {

using namespace nb::literals;

namespace {

// np.asarray(obj), refused with a TypeError naming `what` unless it holds real numbers.
nb::object numeric_array(nb::handle obj, const char* what) {
  nb::object arr;
  try {
    arr = nb::module_::import_("numpy").attr("asarray")(obj);
  } catch (const nb::python_error&) {
    throw nb::type_error((std::string(what) + ": expected an array of numbers").c_str());
  }
  const std::string kind = nb::cast<std::string>(arr.attr("dtype").attr("kind"));
  if (kind != "f" && kind != "i" && kind != "u")
    throw nb::type_error((std::string(what) + ": expected an array of real numbers, got dtype " +
                          nb::cast<std::string>(arr.attr("dtype").attr("__str__")()))
                             .c_str());
  return arr;
}

// obj as a C-contiguous array of T (a copy unless it already is one), after checking it holds numbers.
template <class T>
nb::ndarray<const T, nb::c_contig, nb::device::cpu> as_array(nb::handle obj, const char* what) {
  using Array = nb::ndarray<const T, nb::c_contig, nb::device::cpu>;
  Array a;
  if (nb::try_cast(obj, a, false)) return a;  // already one: no copy
  nb::object arr = numeric_array(obj, what);
  if (!nb::try_cast(arr, a, true)) throw nb::type_error((std::string(what) + ": cannot convert to an array").c_str());
  return a;
}

template <class A>
std::string shape_of(const A& a) {
  std::string s = "(";
  for (std::size_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

}  // namespace

Vec3View vec3_view(glm::dvec3& v) { return Vec3View(&v.x, {3}, nb::handle()); }

Mat3View mat3_view(glm::dmat3& m) {
  // glm is column-major (m[col][row]): element (row, col) sits at col * 3 + row.
  const std::int64_t strides[2] = {1, 3};
  const std::size_t shape[2] = {3, 3};
  return Mat3View(&m[0][0], 2, shape, nb::handle(), strides);
}

Vec3View vec3_copy(const glm::dvec3& v) {
  auto* d = new double[3]{v.x, v.y, v.z};
  nb::capsule owner(d, [](void* q) noexcept { delete[] static_cast<double*>(q); });
  return Vec3View(d, {3}, owner);
}

nb::ndarray<nb::numpy, double, nb::ndim<1>> doubles_copy(const std::vector<double>& values) {
  auto* d = new double[values.size() + 1];
  std::copy(values.begin(), values.end(), d);
  nb::capsule owner(d, [](void* q) noexcept { delete[] static_cast<double*>(q); });
  return nb::ndarray<nb::numpy, double, nb::ndim<1>>(d, {values.size()}, owner);
}

glm::dvec3 to_vec3(nb::handle obj, const char* what) {
  const auto a = as_array<double>(obj, what);
  if (a.ndim() != 1 || a.shape(0) != 3)
    throw nb::value_error((std::string(what) + ": expected 3 numbers (shape (3,)), got shape " + shape_of(a)).c_str());
  return {a.data()[0], a.data()[1], a.data()[2]};
}

glm::dmat3 to_mat3(nb::handle obj, const char* what) {
  const auto a = as_array<double>(obj, what);
  if (a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3)
    throw nb::value_error((std::string(what) + ": expected a 3x3 matrix, got shape " + shape_of(a)).c_str());
  glm::dmat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m[c][r] = a.data()[r * 3 + c];
  return m;
}

PressureImage to_pressure(nb::handle obj, const char* what) {
  const auto f = as_array<float>(obj, what);
  if (f.ndim() != 1 && f.ndim() != 2)
    throw nb::value_error((std::string(what) +
                           ": expected a pressure image of shape (rows, cols) or (rows*cols,), got shape " +
                           shape_of(f))
                              .c_str());
  if (f.size() == 0) throw nb::value_error((std::string(what) + ": the pressure image is empty").c_str());
  PressureImage image{{f.data(), f.data() + f.size()}};
  if (f.ndim() == 2) {
    image.rows = static_cast<int>(f.shape(0));
    image.cols = static_cast<int>(f.shape(1));
  }
  return image;
}

// The library's own parsing and names (one policy for every command and for Python).
BackendKind to_backend(const std::string& text, const std::string& what) { return parse_backend_kind(text, what); }

const char* backend_name(BackendKind kind) { return backend_kind_name(kind); }

nb::module_ tools_module() { return nb::module_::import_("sva._sva_eval"); }

nb::object loaded_tools_module() {
  nb::dict modules = nb::borrow<nb::dict>(nb::module_::import_("sys").attr("modules"));
  return modules.contains("sva._sva_eval") ? nb::object(modules["sva._sva_eval"]) : nb::object();
}

namespace {
bool on_main_thread() {
  nb::module_ threading = nb::module_::import_("threading");
  return threading.attr("current_thread")().is(threading.attr("main_thread")());
}
}  // namespace

EngineScope::EngineScope(bool interruptible) : armed_(interruptible && on_main_thread()) {
  if (!armed_) return;
  sigaction(SIGINT, nullptr, &previous_int_);
  sigaction(SIGTERM, nullptr, &previous_term_);
  util::clear_interrupt();
  util::install_interrupt_handler();
}

EngineScope::~EngineScope() {
  if (!armed_) return;
  sigaction(SIGINT, &previous_int_, nullptr);
  sigaction(SIGTERM, &previous_term_, nullptr);
  util::clear_interrupt();
}

}  // namespace sva::python
