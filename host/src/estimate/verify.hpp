#pragma once
// Stage 3 of the estimate (estimate/pipeline.hpp): verify the leading objects against their surfaces
// (docs/recognition.md, "Surface check"). Eq 5 votes with pairs of readings whose keys (appearance classes and a
// distance bin) near-twins share: a clamp and its larger copy, a brick of 2x2 and of 2x4 studs agree on most pairs,
// and the belief may settle on the wrong one. The surface knows more: the larger clamp's readings lie off the
// smaller one's surface wherever the pose puts it. Each reading counts once here, unlike Eq 5's pairs; its bits
// enter the posterior with the calibration's learned surface weight (stage 4), which discounts the sampling noise
// of the training contacts.
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "estimate/fit.hpp"
#include "estimate/surface_model.hpp"
#include "map/pair_map.hpp"
#include "map/surface_index.hpp"
#include "reading/observed_reading.hpp"

namespace sva {

// A reading's fit: a Gaussian of the residual's joint scale (point-to-plane and normal tilt, as the fine pose
// weighs them) with sigma half the fine pose's final scale (1 mm in 8 mm bins: the arm's 0.5 mm and the gaps
// between training contacts), and a floor for readings the surface does not explain (2^-6.6: an outlier costs
// 6.6 bits, so that one odd reading cannot overrule the pairs' evidence, a few can).
inline constexpr double kSurfaceSigmaOfScale = 0.5;
inline constexpr double kSurfaceFloor = 0.01;
// The measurement model's normal misfit scale: a mesh's facet normal is exact, unlike a training contact's noisy
// one, so the normal weighs as much as the position. Measured on lookalikes' test readings against their true
// meshes: |n_obs - n_facet| median 0.033, p75 0.08, p95 1.1 (edges); the contact's distance to the surface median
// -0.28 mm, p5-p95 -1.15 to 0.63 mm.
inline constexpr double kMeshTiltSigma = 0.1;
// The pad's image against the surface under it (SurfaceModel::pad_misfit): the misfit's scale in mm of penetration.
// lookalikes' sensor: 0.3 kPa of noise and offset and 5% gain at 100 kPa/mm are 0.003-0.01 mm; the skin's 0.6 mm
// spread, which the model does not press, blurs an edge by a few hundredths.
inline constexpr double kPadSigmaMm = 0.08;

struct Verification {
  // Per object (empty when not run): the fit in bits for the fitted leading objects, the worst of theirs for the
  // others (not fitted because the evidence already ranks them lower; never favoured by the check).
  std::vector<double> log2_fit;
};

// The measurement model's noise at `settings` (the fine pose's final scale, the normal at kMeshTiltSigma), its reach 4
// sigma: past it a reading's Gaussian term is 3% of the floor. A map's surface model looks no farther.
ContactNoise contact_noise(const RefineSettings& settings);
// The measurement model of `map`'s surfaces, its reach the map's own pose space's; none when the map
// carries no surfaces.
std::unique_ptr<SurfaceModel> surface_model_of(const PairMap& map);

// How well each leading object of `fits` explains `readings`; empty without leading fits. With the map's surfaces
// (`model`), the measurement model at each of the leading fits' poses, the best of them: every object is tried at
// the same poses, so that two copies of one mesh score alike, bit for bit. Without (a map of recordings, or of
// format 8 and older), the training contacts at the object's own fine pose.
Verification verify_candidates(const Fits& fits, std::span<const ObservedReading> readings, const SurfaceIndex& surface,
                               const RefineSettings& settings, std::size_t objects,
                               const SurfaceModel* model = nullptr);

}  // namespace sva
