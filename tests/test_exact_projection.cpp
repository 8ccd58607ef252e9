// The exact projection of a few bodies' velocities onto contact constraints (exact_projection.h),
// without a world: checked against the Karush-Kuhn-Tucker conditions, which hold at the projection and
// nowhere else (the problem is strictly convex), and against analytic answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "contact/exact_projection.h"

namespace {

using rattle::Vec2;
using rattle::detail::projectExactly;
using rattle::detail::ProjectionRow;
using rattle::detail::ProjectionScratch;

struct Residuals {
  double infeasible = 0;     // most a constraint is missed by
  double negative = 0;       // most negative impulse
  double complementary = 0;  // largest impulse x slack
  double stationary = 0;     // largest |M (v - v0) - sum of impulses along normals|
};

Residuals residuals(const std::vector<double>& inverseMass, const std::vector<Vec2>& v0, const std::vector<Vec2>& v,
                    const std::vector<ProjectionRow>& rows, const std::vector<double>& lambda) {
  Residuals r;
  std::vector<Vec2> force(v.size());
  for (size_t k = 0; k < v.size(); ++k) force[k] = (v[k] - v0[k]) * (1.0 / inverseMass[k]);
  for (size_t i = 0; i < rows.size(); ++i) {
    const ProjectionRow& row = rows[i];
    const Vec2 vb = row.kb >= 0 ? v[row.kb] : Vec2{};
    const double slack = dot(v[row.ka] - vb, row.normal) - row.target;
    r.infeasible = std::max(r.infeasible, -slack);
    r.negative = std::max(r.negative, -lambda[i]);
    r.complementary = std::max(r.complementary, std::fabs(lambda[i] * slack));
    force[row.ka] -= row.normal * lambda[i];
    if (row.kb >= 0) force[row.kb] += row.normal * lambda[i];
  }
  for (const Vec2& f : force) r.stationary = std::max(r.stationary, length(f));
  return r;
}

double kinetic(const std::vector<double>& inverseMass, const std::vector<Vec2>& v) {
  double e = 0;
  for (size_t k = 0; k < v.size(); ++k) e += 0.5 * dot(v[k], v[k]) / inverseMass[k];
  return e;
}

Vec2 unit(double angle) { return {std::cos(angle), std::sin(angle)}; }

TEST(ExactProjection, RandomIslandsMeetTheOptimalityConditions) {
  // Random islands of 2 to 24 bodies with masses over three decades, many rows each (some repeated,
  // some sums of others: the dependent contacts a disk in a polygon's corner makes). Every target is
  // <= 0, so zero velocity is feasible and the projection exists.
  std::mt19937_64 random(20261128);
  std::uniform_real_distribution<double> unitInterval(0.0, 1.0);
  int solved = 0;
  ProjectionScratch scratch;  // one for every trial: what a world does
  for (int trial = 0; trial < 400; ++trial) {
    const size_t members = 2 + random() % 23;
    std::vector<double> inverseMass(members);
    std::vector<Vec2> v0(members);
    for (size_t k = 0; k < members; ++k) {
      inverseMass[k] = std::pow(10.0, -3 * unitInterval(random));
      v0[k] = unit(6.283185307179586 * unitInterval(random)) * (10 * unitInterval(random));
    }
    std::vector<ProjectionRow> rows;
    const size_t rowCount = members + random() % (4 * members);
    for (size_t i = 0; i < rowCount; ++i) {
      ProjectionRow row;
      row.ka = static_cast<int>(random() % members);
      row.kb = unitInterval(random) < 0.3 ? -1 : static_cast<int>(random() % members);
      if (row.kb == row.ka) row.kb = -1;
      row.normal = unit(6.283185307179586 * unitInterval(random));
      row.target = unitInterval(random) < 0.5 ? 0.0 : -unitInterval(random);
      rows.push_back(row);
      if (unitInterval(random) < 0.2) rows.push_back(row);  // the same contact twice
    }
    std::vector<Vec2> v = v0;
    std::vector<double> lambda;
    if (!projectExactly(inverseMass, v, rows, lambda, 1e-12, scratch)) continue;
    ++solved;
    const Residuals r = residuals(inverseMass, v0, v, rows, lambda);
    const double scale = 10 * 1000;  // speeds up to 10, masses up to 1000
    EXPECT_LE(r.infeasible, 1e-11) << "trial " << trial;
    EXPECT_LE(r.negative, 0.0) << "trial " << trial;
    EXPECT_LE(r.complementary, 1e-9 * scale) << "trial " << trial;
    EXPECT_LE(r.stationary, 1e-9 * scale) << "trial " << trial;
    EXPECT_LE(kinetic(inverseMass, v), kinetic(inverseMass, v0)) << "trial " << trial;
  }
  // Round-off may make the method give up on a degenerate island (the caller then keeps its sweeps), but
  // not often.
  EXPECT_GE(solved, 396);
}

TEST(ExactProjection, HeavyDiskPressingARowIntoAWallStopsTheRow) {
  // A disk 500 times heavier than each of eleven touching disks drives them into a wall at 41 units/s
  // (fuzz/regressions/world_api/budget-hybrid-heavy-disk-crushes-a-row, where Gauss-Seidel needed tens
  // of thousands of sweeps). Inelastic contacts: everything stops, and every contact carries the heavy
  // disk's momentum.
  const size_t light = 11;
  std::vector<double> inverseMass(light + 1, 1.0);
  inverseMass[light] = 1.0 / 500;
  std::vector<Vec2> v(light + 1, Vec2{});
  v[light] = {-41, 0};
  std::vector<ProjectionRow> rows;
  rows.push_back({0, -1, {1, 0}, 0.0});  // the wall, on the left
  for (size_t k = 0; k < light; ++k) rows.push_back({static_cast<int>(k + 1), static_cast<int>(k), {1, 0}, 0.0});
  std::vector<double> lambda;
  ProjectionScratch scratch;
  ASSERT_TRUE(projectExactly(inverseMass, v, rows, lambda, 1e-12, scratch));
  for (size_t k = 0; k <= light; ++k) {
    EXPECT_NEAR(v[k].x, 0.0, 1e-12) << k;
    EXPECT_EQ(v[k].y, 0.0) << k;
  }
  for (size_t i = 0; i < rows.size(); ++i) EXPECT_NEAR(lambda[i], 500 * 41.0, 1e-9) << i;
}

TEST(ExactProjection, TwoDisksMeetingHeadOnMoveOnWithTheirCentreOfMass) {
  // Perfectly inelastic: both leave with the centre of mass's velocity, (2 * 3 - 1 * 1) / 3.
  std::vector<double> inverseMass{0.5, 1.0};
  std::vector<Vec2> v{{3, 1}, {-1, 2}};
  const std::vector<ProjectionRow> rows{{1, 0, {1, 0}, 0.0}};
  std::vector<double> lambda;
  ProjectionScratch scratch;
  ASSERT_TRUE(projectExactly(inverseMass, v, rows, lambda, 1e-12, scratch));
  EXPECT_NEAR(v[0].x, 5.0 / 3, 1e-14);
  EXPECT_NEAR(v[1].x, 5.0 / 3, 1e-14);
  EXPECT_EQ(v[0].y, 1.0);
  EXPECT_EQ(v[1].y, 2.0);
  EXPECT_NEAR(lambda[0], 2 * (3 - 5.0 / 3), 1e-13);
}

TEST(ExactProjection, ContradictoryConstraintsAreRefusedAndChangeNothing) {
  // Two walls that both push the same body away faster than the other lets it go.
  std::vector<double> inverseMass{1.0};
  std::vector<Vec2> v{{0.25, -0.5}};
  const std::vector<ProjectionRow> rows{{0, -1, {1, 0}, 1.0}, {0, -1, {-1, 0}, 1.0}};
  std::vector<double> lambda{7.0};
  ProjectionScratch scratch;
  EXPECT_FALSE(projectExactly(inverseMass, v, rows, lambda, 1e-12, scratch));
  EXPECT_EQ(v[0].x, 0.25);
  EXPECT_EQ(v[0].y, -0.5);
  ASSERT_EQ(lambda.size(), 1u);
  EXPECT_EQ(lambda[0], 7.0);
}

}  // namespace
