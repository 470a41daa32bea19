// sva::Error -> sva.Error (a RuntimeError) with the same message; sva::Interrupted (Ctrl-C inside the engine) ->
// KeyboardInterrupt.
#include <sva/error.hpp>

#include "bindings.hpp"

namespace sva::python {

void bind_errors(nb::module_& m) {
  static nb::exception<Error> error(m, "Error", PyExc_RuntimeError);
  error.attr("__doc__") =
      "An error a user can cause (a bad file, option or value), with the engine's message naming the file or value "
      "and the fault.";
  nb::register_exception_translator([](const std::exception_ptr& p, void*) {
    try {
      std::rethrow_exception(p);
    } catch (const Interrupted& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });
}

}  // namespace sva::python
