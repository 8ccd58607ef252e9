// The exact projection of a few bodies' velocities onto their contacts' constraints.
//
// An island's contact solve is the projection of its members' velocities v0 onto
// { v : n_i . (v_a - v_b) >= target_i for every contact i } in the metric of the masses:
// minimise 1/2 (v - v0)^T M (v - v0) under those constraints, a strictly convex quadratic program whose
// multipliers are the contacts' impulses. Projected Gauss-Seidel (island.cpp) converges slowly where the
// masses differ a lot: a light disk between a wall and a disk 500 times heavier takes an impulse a sweep
// that stops only itself, and the heavy disk loses a 500th of its speed per sweep (tens of thousands of
// sweeps). For a few bodies the program is solved exactly instead, by the dual active-set method of
// Goldfarb and Idnani (1983): it starts from v0, adds the most violated constraint at a time, drops one
// whose multiplier would turn negative, and keeps the active normals linearly independent, so the many
// dependent contacts of a disk in a polygon's corner (one per edge) need no care. In the variables
// y = M^(1/2) v the metric is the identity, which turns the method's steps into a Gram-Schmidt basis of
// the active normals.
#pragma once

#include <vector>

#include "rattle/vec2.h"

namespace rattle::detail {

/// One constraint n . (v[ka] - v[kb]) >= target; kb < 0 when the other body is held fixed (its velocity
/// already counted in target).
struct ProjectionRow {
  int ka = 0, kb = -1;
  Vec2 normal;
  double target = 0;
};

/// Buffers a projection works in, kept between calls so that once they are large enough it allocates
/// nothing.
struct ProjectionScratch {
  std::vector<double> scale, y, start, normals, norm, w, z, steps, q, r, multipliers;
  std::vector<size_t> activeRows;
  std::vector<char> isActive;
};

/// Members at most for which an island solve tries the exact projection.
constexpr size_t kExactProjectionMembers = 24;
/// Without gravity the projection is tried only when the sweeps did not settle, so it may take larger
/// islands: a jam of 27 around a light disk between a wall and a large disk (masses 225 apart) stopped
/// its 300 sweeps far from the answer, was refused, and its bounces took a step's whole budget
/// (fuzz/regressions/world_api/budget-hybrid-disk-between-a-wall-and-a-wedged-disk).
constexpr size_t kExactProjectionMembersWithoutGravity = 64;

/// Projects v (the members' velocities; inverseMass > 0 for each) onto the rows' constraints. On success
/// v holds the projection, lambda each row's impulse (>= 0, 0 for a row not pressed), and every
/// constraint is met within `tolerance` (a velocity); on failure (infeasible, or round-off cycling) it
/// returns false and leaves v and lambda as they were.
bool projectExactly(const std::vector<double>& inverseMass, std::vector<Vec2>& v,
                    const std::vector<ProjectionRow>& rows, std::vector<double>& lambda, double tolerance,
                    ProjectionScratch& scratch);

}  // namespace rattle::detail
