// The dual active-set method of Goldfarb and Idnani (Math. Programming 27, 1983) for
// min 1/2 |y - y0|^2 subject to c_i . y >= b_i, with y = M^(1/2) v, so that c_i . y = n_i . (v_a - v_b).
// The active normals N are kept as N = Q R (Q orthonormal, R upper triangular): the step direction
// for a new constraint p is its part z outside span(N), and r = R^-1 Q^T c_p says how the active
// multipliers must change to keep their constraints met while p's grows.
#include "contact/exact_projection.h"

#include <cmath>
#include <limits>

namespace rattle::detail {

namespace {

// Rows at most: the dense normals cost rows x 2 members doubles (4 MB at 64 members). A long step
// reaches far: 25 disks and a disk made overlapping two boxes' walls, a step of 1 s, gave 514 contacts
// (fuzz/regressions/world_api/budget-hybrid-disk-in-a-corner-by-a-wedged-heavy-disk).
constexpr size_t kMaxRows = 4096;

double dotDense(const double* a, const double* b, size_t n) {
  double s = 0;
  for (size_t i = 0; i < n; ++i) s += a[i] * b[i];
  return s;
}

// The active set as N = Q R, its multipliers, and the rows it holds, in the scratch's buffers: at most n
// rows are active (their normals are independent), so Q and R have at most n columns.
class ActiveSet {
 public:
  ActiveSet(size_t n, ProjectionScratch& s) : n_(n), q_(s.q), r_(s.r), rows_(s.activeRows), u_(s.multipliers) {
    q_.resize(n * n);
    r_.resize(n * n);
    rows_.resize(n);
    u_.resize(n);
  }

  size_t size() const { return count_; }
  size_t row(size_t j) const { return rows_[j]; }
  double& multiplier(size_t j) { return u_[j]; }

  // w = Q^T c and z = c - Q w, orthogonalised twice (classical Gram-Schmidt run twice is as good as
  // modified Gram-Schmidt, Giraud et al. 2005), against the first `columns` columns of Q.
  void split(const double* c, double* w, double* z, size_t columns) const {
    for (size_t i = 0; i < n_; ++i) z[i] = c[i];
    for (size_t j = 0; j < columns; ++j) w[j] = 0;
    for (int pass = 0; pass < 2; ++pass) {
      for (size_t j = 0; j < columns; ++j) {
        const double* qj = &q_[j * n_];
        const double s = dotDense(qj, z, n_);
        w[j] += s;
        for (size_t i = 0; i < n_; ++i) z[i] -= s * qj[i];
      }
    }
  }
  void split(const double* c, double* w, double* z) const { split(c, w, z, count_); }

  // x = R^-1 w by back substitution (R's column j is r_[j * n_ .. j * n_ + j]).
  void solveR(const double* w, double* x) const {
    for (size_t j = 0; j < count_; ++j) x[j] = w[j];
    for (size_t j = count_; j-- > 0;) {
      x[j] /= r_[j * n_ + j];
      for (size_t i = 0; i < j; ++i) x[i] -= r_[j * n_ + i] * x[j];
    }
  }

  void add(size_t row, const double* w, const double* z, double zNorm, double multiplier) {
    setColumn(count_, w, z, zNorm);
    rows_[count_] = row;
    u_[count_] = multiplier;
    ++count_;
  }

  // Drops the k-th active row and factors the columns after it again (drops are rarer than adds).
  void drop(size_t k, const std::vector<double>& normals, double* w, double* z) {
    for (size_t j = k; j + 1 < count_; ++j) {
      rows_[j] = rows_[j + 1];
      u_[j] = u_[j + 1];
    }
    --count_;
    for (size_t j = k; j < count_; ++j) {
      split(&normals[rows_[j] * n_], w, z, j);
      setColumn(j, w, z, std::sqrt(dotDense(z, z, n_)));
    }
  }

 private:
  void setColumn(size_t j, const double* w, const double* z, double zNorm) {
    for (size_t i = 0; i < j; ++i) r_[j * n_ + i] = w[i];
    r_[j * n_ + j] = zNorm;
    for (size_t i = 0; i < n_; ++i) q_[j * n_ + i] = z[i] / zNorm;
  }

  size_t n_;
  size_t count_ = 0;
  std::vector<double>& q_;  // column j at j * n_
  std::vector<double>& r_;
  std::vector<size_t>& rows_;
  std::vector<double>& u_;
};

}  // namespace

bool projectExactly(const std::vector<double>& inverseMass, std::vector<Vec2>& v,
                    const std::vector<ProjectionRow>& rows, std::vector<double>& lambda, double tolerance,
                    ProjectionScratch& scratch) {
  const size_t members = v.size(), n = 2 * members;
  if (rows.size() > kMaxRows || !(tolerance > 0) || members == 0) return false;
  std::vector<double>& scale = scratch.scale;  // sqrt of each inverse mass: v = scale * y
  scale.resize(members);
  for (size_t k = 0; k < members; ++k) {
    if (!(inverseMass[k] > 0) || !std::isfinite(inverseMass[k])) return false;
    scale[k] = std::sqrt(inverseMass[k]);
  }
  std::vector<double>& y = scratch.y;
  y.resize(n);
  for (size_t k = 0; k < members; ++k) {
    y[2 * k] = v[k].x / scale[k];
    y[2 * k + 1] = v[k].y / scale[k];
  }
  std::vector<double>& start = scratch.start;
  start = y;
  std::vector<double>& normals = scratch.normals;  // row i at i * n
  normals.assign(rows.size() * n, 0.0);
  std::vector<double>& norm = scratch.norm;
  norm.resize(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    const ProjectionRow& row = rows[i];
    if (row.ka < 0 || static_cast<size_t>(row.ka) >= members || row.kb >= static_cast<int>(members) || row.kb == row.ka)
      return false;
    double* c = &normals[i * n];
    c[2 * row.ka] = row.normal.x * scale[row.ka];
    c[2 * row.ka + 1] = row.normal.y * scale[row.ka];
    if (row.kb >= 0) {
      c[2 * row.kb] = -row.normal.x * scale[row.kb];
      c[2 * row.kb + 1] = -row.normal.y * scale[row.kb];
    }
    norm[i] = std::sqrt(dotDense(c, c, n));
    if (!(norm[i] > 0) || !std::isfinite(rows[i].target)) return false;
  }
  // A row's value n . (v_a - v_b) in y from its two members alone.
  auto value = [&](size_t i) {
    const ProjectionRow& row = rows[i];
    const double* c = &normals[i * n];
    double s = c[2 * row.ka] * y[2 * row.ka] + c[2 * row.ka + 1] * y[2 * row.ka + 1];
    if (row.kb >= 0) s += c[2 * row.kb] * y[2 * row.kb] + c[2 * row.kb + 1] * y[2 * row.kb + 1];
    return s;
  };

  ActiveSet active(n, scratch);
  std::vector<char>& isActive = scratch.isActive;
  isActive.assign(rows.size(), 0);
  std::vector<double>& w = scratch.w;
  std::vector<double>& z = scratch.z;
  std::vector<double>& r = scratch.steps;
  w.resize(n);
  z.resize(n);
  r.resize(n);
  const double infinity = std::numeric_limits<double>::infinity();
  // Each add or drop is one pass; in exact arithmetic the method ends after finitely many, and round-off
  // that makes it cycle ends here as a failure (the caller falls back on its sweeps).
  int passes = 4 * static_cast<int>(rows.size() + n) + 16;
  for (;;) {
    // The most violated row (ties to the lowest index).
    size_t p = rows.size();
    double worst = -tolerance;
    for (size_t i = 0; i < rows.size(); ++i) {
      if (isActive[i]) continue;
      const double s = value(i) - rows[i].target;
      if (s < worst) {
        worst = s;
        p = i;
      }
    }
    if (p == rows.size()) break;
    const double* cp = &normals[p * n];
    double up = 0;  // p's multiplier while it is being added
    for (;;) {
      if (--passes < 0) return false;
      active.split(cp, w.data(), z.data());
      active.solveR(w.data(), r.data());
      const double zNorm = std::sqrt(dotDense(z.data(), z.data(), n));
      // Within round-off of the active normals' span: p's constraint is met by moving multipliers only.
      const bool dependent = !(zNorm > 1e-9 * norm[p]);
      const double s = value(p) - rows[p].target;
      const double fullStep = dependent ? infinity : -s / dotDense(z.data(), cp, n);
      double partialStep = infinity;
      size_t blocking = active.size();
      for (size_t j = 0; j < active.size(); ++j) {
        if (!(r[j] > 0)) continue;
        const double t = active.multiplier(j) / r[j];
        if (t < partialStep) {
          partialStep = t;
          blocking = j;
        }
      }
      const double t = std::min(fullStep, partialStep);
      if (t == infinity) return false;  // infeasible
      if (!dependent) {
        for (size_t i = 0; i < n; ++i) y[i] += t * z[i];
      }
      for (size_t j = 0; j < active.size(); ++j) active.multiplier(j) = std::max(0.0, active.multiplier(j) - t * r[j]);
      up += t;
      if (!dependent && fullStep <= partialStep) {
        active.add(p, w.data(), z.data(), zNorm, up);
        isActive[p] = 1;
        break;
      }
      isActive[active.row(blocking)] = 0;
      active.drop(blocking, normals, w.data(), z.data());
    }
  }
  // As changes, so that a body no impulse reached keeps its velocity to the bit.
  for (size_t k = 0; k < members; ++k)
    v[k] += Vec2{(y[2 * k] - start[2 * k]) * scale[k], (y[2 * k + 1] - start[2 * k + 1]) * scale[k]};
  lambda.assign(rows.size(), 0.0);
  for (size_t j = 0; j < active.size(); ++j) lambda[active.row(j)] = active.multiplier(j);
  return true;
}

}  // namespace rattle::detail
