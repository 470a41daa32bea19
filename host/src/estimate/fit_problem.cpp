#include "estimate/fit_problem.hpp"

#include <sva/base/parallel.hpp>
#include <sva/base/so3.hpp>

#include <algorithm>
#include <cmath>

namespace sva::pose_fit {

namespace {

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

// Adds weight * row row^T to h and weight * residual * row to g. A row's zero entries (four of a tilt row's six) are
// skipped: each would add +-0 to a sum that starts at +0 and so is never -0, which leaves its bits as they are (the
// rows are finite).
void add_row(Mat* h, Vec* g, const Vec& row, double residual, double weight, int d) {
  std::array<int, kMaxDim> nonzero{};
  int n = 0;
  for (int i = 0; i < d; ++i)
    if (row[i] != 0.0) nonzero[n++] = i;
  for (int a = 0; a < n; ++a) {
    const int i = nonzero[a];
    (*g)[i] += weight * row[i] * residual;
    for (int b = 0; b < n; ++b) (*h)[i][nonzero[b]] += weight * row[i] * row[nonzero[b]];
  }
}

}  // namespace

bool ContactCorrespondences::match(const glm::dvec3& y, const glm::dvec3& u, double, glm::dvec3* point,
                                   glm::dvec3* normal, double* d2, NeighbourMemo* memo) const {
  thread_local std::vector<SurfaceNeighbour> nb;
  if (memo)
    surface_.nearest(object_, y, s_.neighbours, &nb, memo);
  else
    surface_.nearest(object_, y, s_.neighbours, &nb);
  const std::vector<SurfacePoint>& pts = surface_.points(object_);
  for (const SurfaceNeighbour& n : nb) {
    const SurfacePoint& sp = pts[n.index];
    if (glm::dot(sp.normal, u) < s_.min_normal_cos) continue;
    *point = sp.position, *normal = sp.normal, *d2 = n.distance_sq;
    return true;
  }
  return false;
}

bool MeshCorrespondences::match(const glm::dvec3& y, const glm::dvec3& u, double radius, glm::dvec3* point,
                                glm::dvec3* normal, double* d2, NeighbourMemo*) const {
  const SurfaceModel::Nearest q = model_.nearest(object_, y, radius);
  if (!q.found || glm::dot(q.normal, u) < s_.min_normal_cos) return false;
  *point = q.point, *normal = q.normal, *d2 = q.d2;
  return true;
}

Problem::Problem(const Correspondences& surface, std::span<const ObservedReading> readings, const RefineSettings& s)
    : surface_(surface), readings_(readings), s_(s), dim_(s.planar ? 3 : 6) {
  for (const ObservedReading& r : readings) centre_ += r.position;
  centre_ /= static_cast<double>(readings.size());
  double spread = 0.0;
  for (const ObservedReading& r : readings) spread += glm::dot(r.position - centre_, r.position - centre_);
  spread_ = std::max(1.0, std::sqrt(spread / static_cast<double>(readings.size())));
}

Match Problem::match(const RigidPose& pose, const ObservedReading& r, double scale, NeighbourMemo* memo) const {
  Match m;
  const glm::dmat3 Rt = glm::transpose(pose.R);
  const glm::dvec3 y = Rt * (r.position - pose.T), u = Rt * r.normal;
  glm::dvec3 point, normal;
  if (!surface_.match(y, u, scale, &point, &normal, &m.d2, memo)) return Match{};
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
  const std::size_t n = readings_.size();
  f.matches.reserve(n);
  const auto matched = [&](std::size_t i) { return match(pose, readings_[i], scale, memos ? &(*memos)[i] : nullptr); };
  // Split: the readings matched side by side in chunks of at least kMinChunk first, then added in their order with the
  // same stop, so the same sum (a match reads only its own reading's memo, which changes no answer).
  constexpr std::size_t kMinChunk = 4;
  const std::size_t chunks = std::min<std::size_t>(s_.reading_threads, n / kMinChunk);
  std::vector<Match> ahead;
  if (chunks > 1) {
    ahead.resize(n);
    const std::size_t size = (n + chunks - 1) / chunks;
    util::parallel_for(
        chunks,
        [&](std::size_t c) {
          for (std::size_t i = c * size; i < std::min(n, (c + 1) * size); ++i) ahead[i] = matched(i);
        },
        s_.reading_threads);
  }
  for (std::size_t i = 0; i < n; ++i) {
    add(&f, ahead.empty() ? matched(i) : ahead[i], scale);
    if (f.cost >= beat) break;
  }
  return f;
}

void Problem::add(Fit* f, const Match& m, double scale) {
  f->cost += m.found ? tukey_cost(m.s2, scale) : scale * scale / 6.0;
  f->inliers += m.found && m.s2 < scale * scale;
  f->matches.push_back(m);
}

Fit Problem::narrowed(const Fit& f, double scale) const {
  Fit g;
  g.matches.reserve(f.matches.size());
  for (const Match& m : f.matches) add(&g, m.found && surface_.within(m.d2, scale) ? m : Match{}, scale);
  return g;
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

std::pair<RigidPose, Fit> Problem::run(const RigidPose& start, int* observable, Fit* start_fit) const {
  RigidPose pose = start;
  *observable = 0;
  std::vector<double> scales;
  for (double c = s_.scale_start_mm; c > s_.scale_final_mm; c *= 0.5) scales.push_back(c);
  scales.push_back(s_.scale_final_mm);
  std::vector<NeighbourMemo> memos(readings_.size());  // each reading's last query: its next is a step away
  Fit f;
  for (std::size_t at = 0; at < scales.size(); ++at) {
    const double c = scales[at];
    // At the next scale the pose is the one the last scale's whole fit weighed: narrowed, not searched again.
    f = at == 0 ? fit(pose, c, &memos) : narrowed(f, c);
    if (start_fit && at == 0) *start_fit = narrowed(f, scales.back());
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

}  // namespace sva::pose_fit
