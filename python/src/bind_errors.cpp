// sva.Error, the exception the engine's errors become (error_translation.cpp): a RuntimeError with the same message;
// sva::Interrupted (Ctrl-C inside the engine) becomes KeyboardInterrupt.
#include <sva/error.hpp>

#include "bindings.hpp"

namespace sva::python {

void bind_errors(nb::module_& m) {
  static nb::exception<Error> error(m, "Error", PyExc_RuntimeError);
  error.attr("__doc__") =
      "An error a user can cause (a bad file, option or value), with the engine's message naming the file or value "
      "and the fault.";
  translate_errors(error);
}

}  // namespace sva::python
