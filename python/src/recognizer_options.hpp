#pragma once
// RecognizerOptions from Python keyword arguments with the C++ names (backend and method as strings), shared by
// every binding that makes a recognizer. Python's default backend is "auto" (the GPU where one is usable, else the
// CPU reference; both give the same answers).
#include <sva/recognizer.hpp>

#include <string>

#include "bindings.hpp"

namespace sva::python {

// The keyword arguments recognizer_options accepts, as the type stubs show them (without and with `threads`, which
// sva.evaluate takes for its trials instead).
#define RECOGNIZER_OPTIONS_SIG_NO_THREADS                                                            \
  "backend: str = 'auto', method: str = 'sva', eps: float = 1e-06, likelihood_cutoff: float = 0.0, " \
  "object_prune_probability: float = 0.0, max_pairs_per_update: int = 0, "                           \
  "belief_budget_bins: int = 4194304, vulkan_device: str = '', "                                     \
  "refine_pose: bool = True, surface_check: bool = True, calibrate: bool = True, unknown_prior: float = 0.1"
#define RECOGNIZER_OPTIONS_SIG RECOGNIZER_OPTIONS_SIG_NO_THREADS ", threads: int = 0"

// Unknown keywords raise TypeError, bad values sva.Error; `what` names the caller in both.
RecognizerOptions recognizer_options(const nb::kwargs& kwargs, const std::string& what);

}  // namespace sva::python
