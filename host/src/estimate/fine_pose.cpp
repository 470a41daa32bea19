#include "estimate/fine_pose.hpp"

#include <sva/base/parallel.hpp>
#include <sva/base/portable_math.hpp>
#include <sva/base/so3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "calibration/calibration.hpp"
#include "estimate/surface_model.hpp"

namespace sva {

namespace {

// The pose is moved by a small motion about the readings' centroid c, in the
// robot frame: x -> exp(w) (x - c) + c + v. Its parameters are (L w, v): the
// rotation scaled by the readings' spread L, so that both halves are in mm and
// the normal equations' eigenvalues compare (a planar space uses w_z, v_x, v_y).
constexpr int kMaxDim = 6;
using Vec = std::array<double, kMaxDim>;
using Mat = std::array<Vec, kMaxDim>;

// One reading matched to a training contact (both in the robot frame under the current pose).
struct Match {
  bool found = false;
  glm::dvec3 point{0.0};   // the training contact
  glm::dvec3 normal{0.0};  // its normal
  double plane = 0.0;      // point-to-plane residual (mm)
  glm::dvec3 tilt{0.0};    // observed normal minus the contact's
  double s2 = 0.0;         // squared joint residual: plane^2 + (normal weight * |tilt|)^2
};

struct Fit {
  double cost = 0.0;
  std::size_t inliers = 0;
  std::vector<Match> matches;
};

// The weighted normal equations of one Gauss-Newton step: h (point-to-plane plus normal tilt) and g, and hs, the
// point-to-plane rows with the observed normals, which judge what the surface constrains.
struct Equations {
  Mat h{}, hs{};
  Vec g{};
};

struct Step {
  Vec delta{};         // in the parameters above
  int observable = 0;  // directions the point-to-plane equations constrain
};

// Tukey's biweight: quadratic near 0, constant (scale^2 / 6) beyond the scale,
// so a wrong match or an unmatched reading costs the same bounded amount.
double tukey_cost(double s2, double c) {
  const double c2 = c * c;
  if (s2 >= c2) return c2 / 6.0;
  const double u = 1.0 - s2 / c2;
  return c2 / 6.0 * (1.0 - u * u * u);
}
double tukey_weight(double s2, double c) {
  const double c2 = c * c;
  if (s2 >= c2) return 0.0;
  const double u = 1.0 - s2 / c2;
  return u * u;
}

// Eigen-decomposition of a symmetric d x d matrix (cyclic Jacobi; d <= 6, so a
// few sweeps): eigenvalues in `values`, eigenvectors in the columns of `vectors`.
void symmetric_eigen(Mat a, int d, Vec* values, Mat* vectors) {
  Mat& v = *vectors;
  for (int i = 0; i < d; ++i)
    for (int j = 0; j < d; ++j) v[i][j] = i == j ? 1.0 : 0.0;
  for (int sweep = 0; sweep < 60; ++sweep) {
    double off = 0.0, total = 0.0;
    for (int i = 0; i < d; ++i)
      for (int j = 0; j < d; ++j) (i == j ? total : off) += a[i][j] * a[i][j];
    if (off <= 1e-30 * (total + off) || off == 0.0) break;
    for (int p = 0; p < d; ++p)
      for (int q = p + 1; q < d; ++q) {
        if (a[p][q] == 0.0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < d; ++k) {  // a <- a J
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < d; ++k) {  // a <- J^T a
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < d; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  for (int i = 0; i < d; ++i) (*values)[i] = a[i][i];
}

// Solves the m x m symmetric positive definite system A y = b (Cholesky);
// false when A is not positive definite.
bool solve_spd(Mat a, Vec b, int m, Vec* y) {
  for (int j = 0; j < m; ++j) {
    double d = a[j][j];
    for (int k = 0; k < j; ++k) d -= a[j][k] * a[j][k];
    if (!(d > 0.0)) return false;
    a[j][j] = std::sqrt(d);
    for (int i = j + 1; i < m; ++i) {
      double s = a[i][j];
      for (int k = 0; k < j; ++k) s -= a[i][k] * a[j][k];
      a[i][j] = s / a[j][j];
    }
  }
  for (int i = 0; i < m; ++i) {
    for (int k = 0; k < i; ++k) b[i] -= a[i][k] * b[k];
    b[i] /= a[i][i];
  }
  for (int i = m - 1; i >= 0; --i) {
    for (int k = i + 1; k < m; ++k) b[i] -= a[k][i] * b[k];
    b[i] /= a[i][i];
  }
  *y = b;
  return true;
}

void add_row(Mat* h, Vec* g, const Vec& row, double residual, double weight, int d) {
  for (int i = 0; i < d; ++i) {
    (*g)[i] += weight * row[i] * residual;
    for (int j = 0; j < d; ++j) (*h)[i][j] += weight * row[i] * row[j];
  }
}

// Where a reading meets the object (object frame): the surface point and normal matched to a contact `y` whose
// normal is `u`, within `radius` of it. Two sources: the map's training contacts, and the object's mesh.
// `memo`: what the last query for the same reading kept (a fit's next step asks again nearby), or null.
class Correspondences {
 public:
  virtual ~Correspondences() = default;
  virtual bool match(const glm::dvec3& y, const glm::dvec3& u, double radius, glm::dvec3* point, glm::dvec3* normal,
                     NeighbourMemo* memo) const = 0;
};

// The training contacts: the first of the nearest few whose normal is compatible (the radius is not used: the
// robust loss decides what a far match is worth).
class ContactCorrespondences final : public Correspondences {
 public:
  ContactCorrespondences(const SurfaceIndex& surface, std::uint32_t object, const RefineSettings& s)
      : surface_(surface), object_(object), s_(s) {}
  bool match(const glm::dvec3& y, const glm::dvec3& u, double, glm::dvec3* point, glm::dvec3* normal,
             NeighbourMemo* memo) const override {
    thread_local std::vector<SurfaceNeighbour> nb;
    if (memo)
      surface_.nearest(object_, y, s_.neighbours, &nb, memo);
    else
      surface_.nearest(object_, y, s_.neighbours, &nb);
    const std::vector<SurfacePoint>& pts = surface_.points(object_);
    for (const SurfaceNeighbour& n : nb) {
      const SurfacePoint& sp = pts[n.index];
      if (glm::dot(sp.normal, u) < s_.min_normal_cos) continue;
      *point = sp.position, *normal = sp.normal;
      return true;
    }
    return false;
  }

 private:
  const SurfaceIndex& surface_;
  std::uint32_t object_;
  RefineSettings s_;
};

// The mesh: the nearest point within the radius (at most the model's reach), facing the contact's way.
class MeshCorrespondences final : public Correspondences {
 public:
  MeshCorrespondences(const SurfaceModel& model, std::uint32_t object, const RefineSettings& s)
      : model_(model), object_(object), s_(s) {}
  bool match(const glm::dvec3& y, const glm::dvec3& u, double radius, glm::dvec3* point, glm::dvec3* normal,
             NeighbourMemo*) const override {
    const SurfaceModel::Nearest q = model_.nearest(object_, y, radius);
    if (!q.found || glm::dot(q.normal, u) < s_.min_normal_cos) return false;
    *point = q.point, *normal = q.normal;
    return true;
  }

 private:
  const SurfaceModel& model_;
  std::uint32_t object_;
  RefineSettings s_;
};

class Problem {
 public:
  Problem(const Correspondences& surface, std::span<const ObservedReading> readings, const RefineSettings& s)
      : surface_(surface), readings_(readings), s_(s), dim_(s.planar ? 3 : 6) {
    for (const ObservedReading& r : readings) centre_ += r.position;
    centre_ /= static_cast<double>(readings.size());
    double spread = 0.0;
    for (const ObservedReading& r : readings) spread += glm::dot(r.position - centre_, r.position - centre_);
    spread_ = std::max(1.0, std::sqrt(spread / static_cast<double>(readings.size())));
  }

  // `memos`: one per reading, kept across one run's fits (run), or null. `beat`: a cost the caller only asks this fit
  // to fall below (a step's candidate against the pose it would replace). The fit stops at the first reading whose
  // running sum reaches it: a sum of non-negative terms, rounded, never falls as it grows, so the whole cost could not
  // have fallen below either, and the caller decides alike. Such a fit's cost and matches are partial: only compared.
  Fit fit(const RigidPose& pose, double scale, std::vector<NeighbourMemo>* memos = nullptr,
          double beat = std::numeric_limits<double>::infinity()) const;
  Equations normal_equations(const Fit& fit, double scale) const;
  Step step(const Fit& fit, double scale) const;
  RigidPose apply(const RigidPose& pose, const Vec& delta, double t) const;
  // One start through every scale; the fit at the final scale.
  std::pair<RigidPose, Fit> run(const RigidPose& start, int* observable) const;

 private:
  Match match(const RigidPose& pose, const ObservedReading& r, double scale, NeighbourMemo* memo) const;
  // A parameter's place in the full (w_x, w_y, w_z, v_x, v_y, v_z).
  int full_index(int i) const { return dim_ == 6 ? i : i + 2; }

  const Correspondences& surface_;
  std::span<const ObservedReading> readings_;
  RefineSettings s_;
  int dim_;
  glm::dvec3 centre_{0.0};
  double spread_ = 1.0;
};

Match Problem::match(const RigidPose& pose, const ObservedReading& r, double scale, NeighbourMemo* memo) const {
  Match m;
  const glm::dmat3 Rt = glm::transpose(pose.R);
  const glm::dvec3 y = Rt * (r.position - pose.T), u = Rt * r.normal;
  glm::dvec3 point, normal;
  if (!surface_.match(y, u, scale, &point, &normal, memo)) return m;
  m.found = true;
  m.point = pose.apply(point);
  m.normal = pose.rotate(normal);
  m.plane = glm::dot(m.normal, r.position - m.point);
  m.tilt = r.normal - m.normal;
  m.s2 = m.plane * m.plane + s_.normal_weight_mm * s_.normal_weight_mm * glm::dot(m.tilt, m.tilt);
  return m;
}

Fit Problem::fit(const RigidPose& pose, double scale, std::vector<NeighbourMemo>* memos, double beat) const {
  Fit f;
  f.matches.reserve(readings_.size());
  for (std::size_t i = 0; i < readings_.size(); ++i) {
    Match m = match(pose, readings_[i], scale, memos ? &(*memos)[i] : nullptr);
    f.cost += m.found ? tukey_cost(m.s2, scale) : scale * scale / 6.0;
    f.inliers += m.found && m.s2 < scale * scale;
    f.matches.push_back(m);
    if (f.cost >= beat) break;
  }
  return f;
}

Equations Problem::normal_equations(const Fit& fit, double scale) const {
  Mat hp{}, hs{}, h{};
  Vec g{};
  const double lw = s_.normal_weight_mm / spread_;
  for (std::size_t i = 0; i < readings_.size(); ++i) {
    const Match& m = fit.matches[i];
    const double w = m.found ? tukey_weight(m.s2, scale) : 0.0;
    if (w <= 0.0) continue;
    const glm::dvec3 b = m.normal, arm = glm::cross(b, readings_[i].position - centre_) / spread_;
    const Vec plane{arm.x, arm.y, arm.z, -b.x, -b.y, -b.z};
    // The same row with the observed normal (the surface's own at the contact):
    // judges which directions the surface constrains (below).
    const glm::dvec3 o = readings_[i].normal, oarm = glm::cross(o, readings_[i].position - centre_) / spread_;
    const Vec seen{oarm.x, oarm.y, oarm.z, -o.x, -o.y, -o.z};
    // d(tilt)/dw = [b]x: the observed normal against the contact's turned by w.
    const Vec tilt[3] = {
        {0.0, -b.z * lw, b.y * lw, 0, 0, 0}, {b.z * lw, 0.0, -b.x * lw, 0, 0, 0}, {-b.y * lw, b.x * lw, 0.0, 0, 0, 0}};
    Vec row{}, unused{};
    for (int k = 0; k < dim_; ++k) row[k] = seen[full_index(k)];
    add_row(&hs, &unused, row, 0.0, w, dim_);
    for (int k = 0; k < dim_; ++k) row[k] = plane[full_index(k)];
    add_row(&hp, &g, row, m.plane, w, dim_);
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < dim_; ++k) row[k] = tilt[c][full_index(k)];
      add_row(&h, &unused, row, 0.0, w, dim_);
      for (int k = 0; k < dim_; ++k) g[k] += w * row[k] * s_.normal_weight_mm * m.tilt[c];
    }
  }
  for (int i = 0; i < dim_; ++i)
    for (int j = 0; j < dim_; ++j) h[i][j] += hp[i][j];
  return {h, hs, g};
}

Step Problem::step(const Fit& fit, double scale) const {
  const auto [h, hs, g] = normal_equations(fit, scale);
  // Observability from point-to-plane equations alone, and with the observed
  // normals: a sliding direction (a plane's slide, a cylinder's spin) moves
  // the contacts along the surface, which the observed normal sees as no
  // change; the training contacts' normals and the normal equations would
  // pin it through the sampling of the contacts only.
  Vec values{};
  Mat vectors{};
  symmetric_eigen(hs, dim_, &values, &vectors);
  double largest = 0.0;
  for (int i = 0; i < dim_; ++i) largest = std::max(largest, values[i]);
  const double floor = std::max(s_.min_information, s_.min_relative_information * largest);
  std::array<int, kMaxDim> keep{};
  Step st;
  for (int i = 0; i < dim_; ++i)
    if (values[i] >= floor) keep[st.observable++] = i;
  if (st.observable == 0) return st;
  // Gauss-Newton restricted to the observable directions: the others stay
  // where the start put them (the histogram's value).
  Mat hr{};
  Vec gr{}, y{};
  for (int a = 0; a < st.observable; ++a) {
    for (int i = 0; i < dim_; ++i) gr[a] -= vectors[i][keep[a]] * g[i];
    for (int b = 0; b < st.observable; ++b)
      for (int i = 0; i < dim_; ++i)
        for (int j = 0; j < dim_; ++j) hr[a][b] += vectors[i][keep[a]] * h[i][j] * vectors[j][keep[b]];
  }
  if (!solve_spd(hr, gr, st.observable, &y)) {
    st.observable = 0;
    return st;
  }
  for (int i = 0; i < dim_; ++i)
    for (int a = 0; a < st.observable; ++a) st.delta[i] += vectors[i][keep[a]] * y[a];
  return st;
}

RigidPose Problem::apply(const RigidPose& pose, const Vec& delta, double t) const {
  Vec full{};
  for (int k = 0; k < dim_; ++k) full[full_index(k)] = t * delta[k];
  const glm::dvec3 w = glm::dvec3(full[0], full[1], full[2]) / spread_, v(full[3], full[4], full[5]);
  const glm::dmat3 turn = so3::exp(w);
  RigidPose out;
  out.R = so3::orthonormalize(turn * pose.R);
  out.T = turn * (pose.T - centre_) + centre_ + v;
  if (s_.planar) out.T.z = pose.T.z;
  return out;
}

std::pair<RigidPose, Fit> Problem::run(const RigidPose& start, int* observable) const {
  RigidPose pose = start;
  *observable = 0;
  std::vector<double> scales;
  for (double c = s_.scale_start_mm; c > s_.scale_final_mm; c *= 0.5) scales.push_back(c);
  scales.push_back(s_.scale_final_mm);
  std::vector<NeighbourMemo> memos(readings_.size());  // each reading's last query: its next is a step away
  Fit f;
  for (double c : scales) {
    f = fit(pose, c, &memos);
    for (int it = 0; it < s_.iterations; ++it) {
      const Step st = step(f, c);
      *observable = st.observable;
      if (st.observable == 0) break;
      // Halve the step until the robust cost drops; none that does ends this scale.
      bool accepted = false;
      for (double t = 1.0; t > 0.06 && !accepted; t *= 0.5) {
        const RigidPose candidate = apply(pose, st.delta, t);
        Fit fc = fit(candidate, c, &memos, f.cost);
        if (fc.cost < f.cost) {
          pose = candidate;
          f = std::move(fc);
          accepted = true;
        }
      }
      double size = 0.0;
      for (int k = 0; k < dim_; ++k) size = std::max(size, std::fabs(st.delta[k]));
      if (!accepted || size < 1e-4) break;
    }
  }
  return {pose, f};
}

}  // namespace

RefineSettings refine_settings(const PoseSpace& space, std::uint32_t fine_pose_from) {
  const PoseSpaceSpec& spec = space.spec();
  const double bin = (spec.translation_max_mm - spec.translation_min_mm) / spec.translation_bins;
  RefineSettings s;
  s.planar = space.planar();
  s.min_readings = Calibration::fine_pose_start(fine_pose_from, s.planar);
  s.scale_start_mm = 2.0 * bin;
  s.scale_final_mm = 0.25 * bin;
  // Light: a training contact's normal is one noisy sample at a point near the
  // reading, not the surface's normal there (paper3d: 4 mm/rad cost accuracy).
  s.normal_weight_mm = 0.125 * bin;
  return s;
}

RefinedPose refine_pose(const SurfaceIndex& surface, std::uint32_t object, std::span<const ObservedReading> readings,
                        std::span<const RigidPose> starts, const RefineSettings& settings) {
  RefinedPose out;
  if (starts.empty()) return out;
  out.pose = starts[0];
  if (readings.size() < std::max<std::size_t>(settings.min_readings, 1) || object >= surface.objects() ||
      surface.points(object).empty())
    return out;
  const ContactCorrespondences contacts(surface, object, settings);
  const Problem problem(contacts, readings, settings);
  const double final_scale = settings.scale_final_mm;
  const Fit unrefined = problem.fit(starts[0], final_scale);
  out.cost = unrefined.cost;
  out.inliers = unrefined.inliers;
  // The starts are fitted side by side on the workers (an estimate's latency on a robot), then weighed in their own
  // order, so the answer does not depend on the thread count.
  std::vector<std::pair<RigidPose, Fit>> runs(starts.size());
  std::vector<int> observables(starts.size(), 0);
  util::parallel_for(
      starts.size(), [&](std::size_t k) { runs[k] = problem.run(starts[k], &observables[k]); }, settings.threads);
  // A later (less probable) mode wins only by a clear margin: half a
  // reading's outlier cost, or a quarter of the cost. Modes the shape cannot
  // tell apart (a cube's faces) fit alike, and the histogram's order stands.
  bool have = false;
  RefinedPose best;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const int observable = observables[k];
    const auto& [pose, f] = runs[k];
    const double margin = std::max(final_scale * final_scale / 12.0, 0.25 * best.cost);
    if (have && !(f.cost < best.cost - margin)) continue;
    have = true;
    best.pose = pose;
    best.refined = true;
    best.start = k;
    best.cost = f.cost;
    best.inliers = f.inliers;
    best.observable = observable;
  }
  // Too few readings explained, or no better than the histogram's own pose:
  // keep the histogram's.
  if (best.inliers < settings.min_readings || !(best.cost < unrefined.cost)) return out;
  return best;
}

RigidPose polish_on_mesh(const SurfaceModel& model, std::uint32_t object, std::span<const ObservedReading> readings,
                         const RigidPose& start, const RefineSettings& settings, const ContactNoise& noise) {
  if (readings.size() < std::max<std::size_t>(settings.min_readings, 1) || object >= model.objects()) return start;
  RefineSettings s = settings;
  // From the model's reach down to the fine pose's final scale: the start is already within a few mm (the fit on
  // the training contacts), and the mesh's exact facets weigh the normal as the model does.
  s.scale_start_mm = noise.reach_mm;
  s.scale_final_mm = std::min(settings.scale_final_mm, noise.reach_mm);
  s.normal_weight_mm = noise.normal_weight_mm;
  const MeshCorrespondences mesh(model, object, s);
  const Problem problem(mesh, readings, s);
  int observable = 0;
  const auto [pose, f] = problem.run(start, &observable);
  const double beat = std::nextafter(f.cost, std::numeric_limits<double>::infinity());  // the start loses above f
  return f.cost < problem.fit(start, s.scale_final_mm, nullptr, beat).cost ? pose : start;
}

double surface_log2_fit(const SurfaceIndex& surface, std::uint32_t object, std::span<const ObservedReading> readings,
                        const RigidPose& pose, const RefineSettings& settings, double sigma_mm, double floor) {
  if (readings.empty() || object >= surface.objects() || surface.points(object).empty())
    return static_cast<double>(readings.size()) * pmath::log2(floor);
  const ContactCorrespondences contacts(surface, object, settings);
  const Problem problem(contacts, readings, settings);
  const Fit f = problem.fit(pose, settings.scale_final_mm);
  double bits = 0.0;
  for (const Match& m : f.matches)
    bits += pmath::log2((m.found ? pmath::exp(-0.5 * m.s2 / (sigma_mm * sigma_mm)) : 0.0) + floor);
  return bits;
}

}  // namespace sva
