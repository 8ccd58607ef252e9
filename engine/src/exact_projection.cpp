// The dual active-set method of Goldfarb and Idnani (Math. Programming 27, 1983) for
// min 1/2 |y - y0|^2 subject to c_i . y >= b_i, with y = M^(1/2) v, so that c_i . y = n_i . (v_a - v_b).
// The active normals N are kept as N = Q R (Q orthonormal, R upper triangular): the step direction
// for a new constraint p is its part z outside span(N), and r = R^-1 Q^T c_p says how the active
// multipliers must change to keep their constraints met while p's grows.
#include "exact_projection.h"

#include <cmath>
#include <limits>

namespace rattle::detail {

namespace {

// Rows at most: the dense normals cost rows x 2 members doubles.
constexpr size_t kMaxRows = 512;

double dotDense(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

// The active set as N = Q R, its multipliers, and the rows it holds.
struct ActiveSet {
  std::vector<std::vector<double>> q;  // orthonormal columns
  std::vector<std::vector<double>> r;  // r[j] is column j of R (length j + 1)
  std::vector<size_t> rows;
  std::vector<double> u;

  // w = Q^T c and z = c - Q w, orthogonalised twice (classical Gram-Schmidt run twice is as good as
  // modified Gram-Schmidt, Giraud et al. 2005).
  void split(const std::vector<double>& c, std::vector<double>& w, std::vector<double>& z) const {
    z = c;
    w.assign(q.size(), 0.0);
    for (int pass = 0; pass < 2; ++pass) {
      for (size_t j = 0; j < q.size(); ++j) {
        const double s = dotDense(q[j], z);
        w[j] += s;
        for (size_t i = 0; i < z.size(); ++i) z[i] -= s * q[j][i];
      }
    }
  }

  // R^-1 w by back substitution.
  std::vector<double> solveR(const std::vector<double>& w) const {
    std::vector<double> x(w);
    for (size_t j = q.size(); j-- > 0;) {
      x[j] /= r[j][j];
      for (size_t i = 0; i < j; ++i) x[i] -= r[j][i] * x[j];
    }
    return x;
  }

  void add(size_t row, const std::vector<double>& w, const std::vector<double>& z, double zNorm, double multiplier) {
    std::vector<double> column(w);
    column.push_back(zNorm);
    r.push_back(std::move(column));
    std::vector<double> unit(z);
    for (double& x : unit) x /= zNorm;
    q.push_back(std::move(unit));
    rows.push_back(row);
    u.push_back(multiplier);
  }

  // Drops the k-th active row and factors the rest again (drops are rarer than adds).
  void drop(size_t k, const std::vector<std::vector<double>>& normals) {
    rows.erase(rows.begin() + static_cast<std::ptrdiff_t>(k));
    u.erase(u.begin() + static_cast<std::ptrdiff_t>(k));
    q.clear();
    r.clear();
    std::vector<double> w, z;
    for (size_t row : rows) {
      split(normals[row], w, z);
      const double zNorm = std::sqrt(dotDense(z, z));
      std::vector<double> column(w);
      column.push_back(zNorm);
      r.push_back(std::move(column));
      for (double& x : z) x /= zNorm;
      q.push_back(z);
    }
  }
};

}  // namespace

bool projectExactly(const std::vector<double>& inverseMass, std::vector<Vec2>& v,
                    const std::vector<ProjectionRow>& rows, std::vector<double>& lambda, double tolerance) {
  const size_t members = v.size(), n = 2 * members;
  if (rows.size() > kMaxRows || !(tolerance > 0)) return false;
  std::vector<double> scale(members);  // sqrt of each inverse mass: v = scale * y
  for (size_t k = 0; k < members; ++k) {
    if (!(inverseMass[k] > 0) || !std::isfinite(inverseMass[k])) return false;
    scale[k] = std::sqrt(inverseMass[k]);
  }
  std::vector<double> y(n);
  for (size_t k = 0; k < members; ++k) {
    y[2 * k] = v[k].x / scale[k];
    y[2 * k + 1] = v[k].y / scale[k];
  }
  const std::vector<double> start = y;
  std::vector<std::vector<double>> normals(rows.size(), std::vector<double>(n, 0.0));
  std::vector<double> norm(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    const ProjectionRow& row = rows[i];
    if (row.ka < 0 || static_cast<size_t>(row.ka) >= members || row.kb >= static_cast<int>(members) || row.kb == row.ka)
      return false;
    normals[i][2 * row.ka] = row.normal.x * scale[row.ka];
    normals[i][2 * row.ka + 1] = row.normal.y * scale[row.ka];
    if (row.kb >= 0) {
      normals[i][2 * row.kb] = -row.normal.x * scale[row.kb];
      normals[i][2 * row.kb + 1] = -row.normal.y * scale[row.kb];
    }
    norm[i] = std::sqrt(dotDense(normals[i], normals[i]));
    if (!(norm[i] > 0) || !std::isfinite(rows[i].target)) return false;
  }

  ActiveSet active;
  std::vector<bool> isActive(rows.size(), false);
  std::vector<double> w, z;
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
      const double s = dotDense(normals[i], y) - rows[i].target;
      if (s < worst) {
        worst = s;
        p = i;
      }
    }
    if (p == rows.size()) break;
    double up = 0;  // p's multiplier while it is being added
    for (;;) {
      if (--passes < 0) return false;
      active.split(normals[p], w, z);
      const std::vector<double> r = active.solveR(w);
      const double zNorm = std::sqrt(dotDense(z, z));
      // Within round-off of the active normals' span: p's constraint is met by moving multipliers only.
      const bool dependent = !(zNorm > 1e-9 * norm[p]);
      const double s = dotDense(normals[p], y) - rows[p].target;
      const double fullStep = dependent ? infinity : -s / dotDense(z, normals[p]);
      double partialStep = infinity;
      size_t blocking = active.rows.size();
      for (size_t j = 0; j < active.rows.size(); ++j) {
        if (!(r[j] > 0)) continue;
        const double t = active.u[j] / r[j];
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
      for (size_t j = 0; j < active.rows.size(); ++j) active.u[j] = std::max(0.0, active.u[j] - t * r[j]);
      up += t;
      if (!dependent && fullStep <= partialStep) {
        active.add(p, w, z, zNorm, up);
        isActive[p] = true;
        break;
      }
      isActive[active.rows[blocking]] = false;
      active.drop(blocking, normals);
    }
  }
  // As changes, so that a body no impulse reached keeps its velocity to the bit.
  for (size_t k = 0; k < members; ++k)
    v[k] += Vec2{(y[2 * k] - start[2 * k]) * scale[k], (y[2 * k + 1] - start[2 * k + 1]) * scale[k]};
  lambda.assign(rows.size(), 0.0);
  for (size_t j = 0; j < active.rows.size(); ++j) lambda[active.rows[j]] = active.u[j];
  return true;
}

}  // namespace rattle::detail
