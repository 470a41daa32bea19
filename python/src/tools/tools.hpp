#pragma once
// The bindings of the tools' module sva._sva_eval (module.cpp), one file per stage.
#include "../bindings.hpp"

namespace sva::python {

void bind_evaluate(nb::module_& m);  // sva.evaluate (sva eval)
void bind_trials(nb::module_& m);    // _eval_trial, for sva.trial_session
void bind_preview(nb::module_& m);   // _write_preview, for sva.simulate(preview=...)

}  // namespace sva::python
