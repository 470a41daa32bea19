#include "appearance/appearance_baseline.hpp"

#include <sva/base/portable_math.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace sva {

AppearanceBaseline AppearanceBaseline::fit(std::uint32_t n_objects, std::uint32_t n_classes,
                                           const std::vector<std::uint32_t>& object,
                                           const std::vector<std::vector<ClassWeight>>& classes, double smoothing) {
  assert(object.size() == classes.size() && smoothing > 0);
  AppearanceBaseline b;
  b.n_objects = n_objects;
  b.n_classes = n_classes;
  b.smoothing = smoothing;
  b.class_given_object.assign(static_cast<std::size_t>(n_objects) * n_classes, smoothing);
  std::vector<double> total(n_objects, smoothing * n_classes);
  for (std::size_t i = 0; i < object.size(); ++i) {
    assert(object[i] < n_objects);
    for (const auto& c : classes[i]) {
      b.class_given_object[static_cast<std::size_t>(object[i]) * n_classes + c.cls] += c.weight;
      total[object[i]] += c.weight;
    }
  }
  for (std::uint32_t o = 0; o < n_objects; ++o)
    for (std::uint32_t c = 0; c < n_classes; ++c)
      b.class_given_object[static_cast<std::size_t>(o) * n_classes + c] /= total[o];
  return b;
}

std::vector<double> AppearanceBaseline::log_likelihood(const std::vector<ClassWeight>& classes) const {
  std::vector<double> out(n_objects, 0.0);
  for (std::uint32_t o = 0; o < n_objects; ++o) {
    double s = 0;
    for (const auto& c : classes) {
      if (c.cls >= n_classes) throw Error("appearance baseline: class " + std::to_string(c.cls) + " out of range");
      s += static_cast<double>(c.weight) * class_given_object[static_cast<std::size_t>(o) * n_classes + c.cls];
    }
    // Smoothing keeps every entry positive; the guard covers an empty class list.
    out[o] = pmath::log(std::max(s, 1e-300));
  }
  return out;
}

void AppearanceBaseline::update(std::vector<double>& log_posterior, const std::vector<ClassWeight>& classes) const {
  if (log_posterior.size() != n_objects) log_posterior.assign(n_objects, 0.0);
  const auto ll = log_likelihood(classes);
  for (std::uint32_t o = 0; o < n_objects; ++o) log_posterior[o] += ll[o];
}

std::vector<double> AppearanceBaseline::posterior(const std::vector<double>& log_posterior) {
  if (log_posterior.empty()) return {};
  const double top = *std::max_element(log_posterior.begin(), log_posterior.end());
  std::vector<double> p(log_posterior.size());
  double sum = 0;
  for (std::size_t i = 0; i < p.size(); ++i) sum += p[i] = pmath::exp(log_posterior[i] - top);
  for (double& v : p) v /= sum;
  return p;
}

}  // namespace sva
