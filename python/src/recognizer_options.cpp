#include "recognizer_options.hpp"

#include <sva/error.hpp>

#include <nanobind/stl/string.h>

#include <cmath>

namespace sva::python {

namespace {

Method to_method(const std::string& text, const std::string& what) {
  if (text == "sva") return Method::sva;
  if (text == "appearance") return Method::appearance;
  throw Error(what + ": method expects \"sva\" or \"appearance\", got \"" + text + "\"");
}

}  // namespace

RecognizerOptions recognizer_options(const nb::kwargs& kwargs, const std::string& what) {
  RecognizerOptions o;
  o.backend = BackendKind::automatic;
  for (auto [k, v] : kwargs) {
    const std::string key = nb::cast<std::string>(k);
    if (key == "backend") {
      o.backend = to_backend(keyword_value<std::string>(v, what, "backend", "a string"), what + ": backend");
    } else if (key == "method") {
      o.method = to_method(keyword_value<std::string>(v, what, "method", "a string"), what);
    } else if (key == "eps") {
      o.eps = keyword_value<double>(v, what, "eps", "a number");
      if (!(o.eps > 0) || !std::isfinite(o.eps)) throw Error(what + ": eps must be a positive number");
    } else if (key == "likelihood_cutoff") {
      o.likelihood_cutoff = static_cast<float>(keyword_value<double>(v, what, "likelihood_cutoff", "a number"));
    } else if (key == "object_prune_probability") {
      o.object_prune_probability = keyword_value<double>(v, what, "object_prune_probability", "a number");
    } else if (key == "max_pairs_per_update") {
      o.max_pairs_per_update = keyword_value<int>(v, what, "max_pairs_per_update", "an int");
    } else if (key == "belief_budget_bins") {
      o.belief_budget_bins = keyword_value<std::size_t>(v, what, "belief_budget_bins", "a non-negative int");
    } else if (key == "threads") {
      o.threads = keyword_value<unsigned>(v, what, "threads", "a non-negative int");
    } else if (key == "vulkan_device") {
      o.vulkan_device = keyword_value<std::string>(v, what, "vulkan_device", "a string");
    } else if (key == "refine_pose") {
      o.refine_pose = keyword_value<bool>(v, what, "refine_pose", "a bool");
    } else if (key == "surface_check") {
      o.surface_check = keyword_value<bool>(v, what, "surface_check", "a bool");
    } else if (key == "calibrate") {
      o.calibrate = keyword_value<bool>(v, what, "calibrate", "a bool");
    } else if (key == "unknown_prior") {
      o.unknown_prior = keyword_value<double>(v, what, "unknown_prior", "a number in (0, 1)");
    } else {
      throw nb::type_error((what + ": unknown option \"" + key +
                            "\" (options: backend, method, eps, likelihood_cutoff, object_prune_probability, "
                            "max_pairs_per_update, belief_budget_bins, threads, vulkan_device, refine_pose, "
                            "surface_check, calibrate, unknown_prior)")
                               .c_str());
    }
  }
  return o;
}

}  // namespace sva::python
