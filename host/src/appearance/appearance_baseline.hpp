#pragma once
// The appearance-only baseline of [15], the paper's comparison: each object
// is a smoothed histogram of the soft appearance classes of its training
// readings, and a naive-Bayes posterior over objects is updated one reading
// at a time (readings assumed independent given the object; pose ignored).
#include <cstdint>
#include <vector>

#include "appearance/appearance_model.hpp"

namespace sva {

class AppearanceBaseline {
 public:
  std::uint32_t n_objects = 0;
  std::uint32_t n_classes = 0;
  double smoothing = 1.0;                  // Laplace pseudo-count per class
  std::vector<double> class_given_object;  // n_objects x n_classes, rows sum to 1

  // Histogram of each object's readings' soft classes (`object[i]` and
  // `classes[i]` per training reading), plus `smoothing` in every class.
  static AppearanceBaseline fit(std::uint32_t n_objects, std::uint32_t n_classes,
                                const std::vector<std::uint32_t>& object,
                                const std::vector<std::vector<ClassWeight>>& classes, double smoothing = 1.0);

  // log Pr(z | object) = log sum_c Pr(z | c) Pr(c | object) for one reading's soft classes.
  std::vector<double> log_likelihood(const std::vector<ClassWeight>& classes) const;
  // Adds one reading's log likelihood to a log posterior (start from zeros: uniform prior).
  void update(std::vector<double>& log_posterior, const std::vector<ClassWeight>& classes) const;
  // Normalised probabilities of a log posterior (log-sum-exp).
  static std::vector<double> posterior(const std::vector<double>& log_posterior);
};

}  // namespace sva
