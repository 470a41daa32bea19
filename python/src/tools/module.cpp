// The extension module sva._sva_eval: the tools' library (evaluation, figures; host/eval) for the package, kept out
// of sva._sva_core so that `import sva`, and a robot's program with it, never loads cairo or the bench kernels. The
// package imports it on first use (sva.evaluate, sva.trial_session, sva.simulate's preview).
//
// It links its own copy of the engine: the classes are sva._sva_core's (nanobind shares them between modules), and
// what the library keeps in globals is this copy's own: whether progress is shown (set here and by
// sva.show_progress), the Ctrl-C flag (armed by this module's EngineScope). Nothing here reads the assets folder.
#include <sva/base/progress.hpp>
#include <sva/error.hpp>

#include "../bindings.hpp"
#include "tools.hpp"

NB_MODULE(_sva_eval, m) {
  using namespace sva;
  using namespace sva::python;
  m.doc() = "sva's tools (evaluation and figures), for sva.evaluate, sva.trial_session and sva.simulate's preview.";
  nb::module_ core = nb::module_::import_("sva._sva_core");
  // sva::Error and sva::Interrupted thrown by this module's copy of the library: the engine module's exception.
  static nb::object error = core.attr("Error");
  translate_errors(error);
  util::Progress::set_quiet(!nb::cast<bool>(core.attr("_progress_shown")()));
  m.def("_show_progress", [](bool on) { util::Progress::set_quiet(!on); });
  bind_evaluate(m);
  bind_trials(m);
  bind_preview(m);
}
