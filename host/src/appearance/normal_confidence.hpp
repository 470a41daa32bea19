#pragma once
// Algorithm 1 (paper Sec 4.2): how well the surface constrained the sensor
// normal, from the contact points the pressure image implies. 1 for a planar
// contact with equal spread in both directions, 0 for point and line contacts.
#include <sva/reading.hpp>

#include <array>
#include <vector>

namespace sva::appearance {

// Eigenvalues of a symmetric 3x3 matrix, largest first (sva/base/symmetric_eigen3.hpp: slow but unconditionally
// stable, and exact enough for a ratio of spreads).
std::array<double, 3> symmetric_eigenvalues(const std::array<std::array<double, 3>, 3>& m);

// Contact points: elements above `threshold_kpa` at their centre (mm), depth
// = pressure / stiffness (the inverse of the skin calibration). Returns the
// ratio of the two largest singular values of the centred points; 0 for fewer
// than 3 points or (numerically) colinear ones.
float normal_confidence(const std::vector<float>& pressure, const SensorSpec& sensor, double stiffness_kpa_per_mm,
                        double threshold_kpa);

}  // namespace sva::appearance
