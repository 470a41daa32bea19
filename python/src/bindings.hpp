#pragma once
// The Python bindings of sva (module sva._sva_core, the engine, re-exported by the package `sva`; the tools' module
// sva._sva_eval in tools/): one bind_* function per public class or stage, each in its own file, so that a change
// of the C++ API touches one small file. Helpers
// shared by them: NumPy conversions of readings and poses, and the scope that releases the GIL around the engine's
// work while keeping Ctrl-C working.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/string.h>

#include <sva/pose.hpp>
#include <sva/recognizer.hpp>

#include <csignal>
#include <string>
#include <vector>

namespace sva::python {

namespace nb = nanobind;

void bind_errors(nb::module_& m);
// Translates sva::Error into `error` (the engine module's sva.Error, kept alive by the caller) and sva::Interrupted
// into KeyboardInterrupt, for what this module's copy of the library throws.
void translate_errors(nb::handle error);
void bind_pose(nb::module_& m);
void bind_pose_space(nb::module_& m);
void bind_scene(nb::module_& m);
void bind_reading(nb::module_& m);
void bind_dataset(nb::module_& m);
void bind_map(nb::module_& m);
void bind_engine(nb::module_& m);
void bind_prior(nb::module_& m);
void bind_recognizer(nb::module_& m);
void bind_batch_recognizer(nb::module_& m);
void bind_workflow(nb::module_& m);
void bind_touch_planner(nb::module_& m);
void bind_sessions(nb::module_& m);

// Read-only NumPy views of engine memory owned by a Python object (rv_policy::reference_internal).
using Vec3View = nb::ndarray<nb::numpy, double, nb::shape<3>>;
using Mat3View = nb::ndarray<nb::numpy, double, nb::shape<3, 3>>;

// A view of a glm vector / column-major matrix as a NumPy (3,) / (3, 3) array (rows and columns as written).
Vec3View vec3_view(glm::dvec3& v);
Mat3View mat3_view(glm::dmat3& m);
// A new NumPy (3,) array holding v.
Vec3View vec3_copy(const glm::dvec3& v);
// A new 1-D NumPy array holding `values`.
nb::ndarray<nb::numpy, double, nb::ndim<1>> doubles_copy(const std::vector<double>& values);

// Array-likes from Python, checked: `what` names the argument in the TypeError (not numbers) or ValueError (wrong
// shape) raised. Values are not checked for NaN here; the engine refuses them with sva.Error, as in C++.
glm::dvec3 to_vec3(nb::handle obj, const char* what);
glm::dmat3 to_mat3(nb::handle obj, const char* what);
// A pressure image: rows x cols (2-D) or flat (1-D), row-major; float32 arrays are read without conversion.
struct PressureImage {
  std::vector<float> values;
  int rows = 0, cols = 0;  // its shape when 2-D (Reading::rows, cols); 0 when flat
};
PressureImage to_pressure(nb::handle obj, const char* what);

// A keyword argument's value as T, or a TypeError "<what>: option <key> expects <type>, got <its type>".
template <class T>
T keyword_value(nb::handle value, const std::string& what, const std::string& key, const char* type) {
  T out{};
  if (!nb::try_cast(value, out))
    throw nb::type_error((what + ": option " + key + " expects " + type + ", got " +
                          nb::cast<std::string>(value.type().attr("__name__")))
                             .c_str());
  return out;
}

// The tools' module sva._sva_eval (evaluation, figures: the tools' library, cairo): imported on first use, so that
// `import sva` loads the engine alone. loaded_tools_module(): the module if imported already, else an invalid handle.
nb::module_ tools_module();
nb::object loaded_tools_module();

// "auto", "cpu", "vulkan" (anything else: sva.Error naming `what`).
BackendKind to_backend(const std::string& text, const std::string& what);
const char* backend_name(BackendKind kind);

// Releases the GIL for the engine's long work (updates, simulation, training, evaluation) and, on the main thread,
// lets Ctrl-C reach the engine: the library's SIGINT flag is armed for the scope (the engine then stops with
// sva::Interrupted, raised as KeyboardInterrupt) and Python's own handler is restored after it.
class EngineScope {
 public:
  explicit EngineScope(bool interruptible = false);
  ~EngineScope();
  EngineScope(const EngineScope&) = delete;
  EngineScope& operator=(const EngineScope&) = delete;

 private:
  bool armed_ = false;
  struct sigaction previous_int_ {
  }, previous_term_{};
  nb::gil_scoped_release release_;
};

}  // namespace sva::python
