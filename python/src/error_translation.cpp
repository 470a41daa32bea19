// sva::Error -> the engine module's sva.Error (a RuntimeError) with the same message; sva::Interrupted (Ctrl-C inside
// the engine) -> KeyboardInterrupt. Compiled into both modules: each has its own copy of the library, so each
// registers the translation of what its copy throws.
#include <sva/error.hpp>

#include "bindings.hpp"

namespace sva::python {

void translate_errors(nb::handle error) {
  nb::register_exception_translator(
      [](const std::exception_ptr& p, void* payload) {
        try {
          std::rethrow_exception(p);
        } catch (const Interrupted& e) {
          PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
        } catch (const Error& e) {
          PyErr_SetString(static_cast<PyObject*>(payload), e.what());
        }
      },
      error.ptr());
}

}  // namespace sva::python
