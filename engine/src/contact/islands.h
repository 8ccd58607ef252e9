// The stepped islands and the jams (island.cpp, jam.cpp): the persistent contact that the hybrid step
// holds by a solve once a step instead of by events. What they keep from step to step (the stepped
// bodies, the warm start, the jams' numbering) belongs to the HybridState that runs them: the hybrid
// stepper's, or the predictive stepper's for the piles and jams it hands over. They read and change the
// world's bodies through `w`, and tell the step that runs them whose motion they changed through
// `predictor`.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "common/body_marks.h"
#include "contact/exact_projection.h"
#include "world/world_impl.h"

namespace rattle::detail {

class EventPredictor;  // stepper.h

struct Islands {
  explicit Islands(WorldState& world) : w(world) {}
  Islands(const Islands&) = delete;
  Islands& operator=(const Islands&) = delete;

  WorldState& w;
  // The step running now that predicts events (the hybrid step), told whose motion a solve changed;
  // null outside it.
  EventPredictor* predictor = nullptr;

  /// At World::step's start, before the step runs: keeps what undoStep puts back.
  void beginStep();
  /// The step failed (out of memory) and the world was taken back to its start: the warm start and the
  /// jams' numbering go back too, and the scratch is made whole.
  void undoStep();

  // island.cpp: stepped islands.
  struct IslandContact {
    uint32_t a, b;    // body indices; b may be static, kinematic, sleeping or a stepped non-member
    uint32_t fa, fb;  // their fixtures
    int ka, kb;       // index into the members, -1 when the body is held fixed
    Vec2 normal;      // from b toward a
    Vec2 point;
    Vec2 holderVelocity;        // b's velocity when it is held fixed
    double inverseA, inverseB;  // 0 for a body held fixed
    double target;              // least relative normal velocity after (-gap / time left)
    double lambda = 0;
    double approach = 0;  // closing speed before the solve
    double gap = 0;       // distance minus radius when the solve starts (< 0: overlap)
    double radius = 0;    // the smaller radius of the pair's disks (the member's, against a holder)
  };
  std::vector<uint32_t> stepped;         // this step's stepped bodies at its start
  std::vector<uint32_t> steppedCounts;   // their collision counters after the start's solve
  std::vector<IslandContact> islandScratch, islandScratchStart;
  bool islandKinematicHolder = false;  // a contact of islandScratch is with a kinematic body (its gather)
  std::vector<IslandContact> islandScratchBefore;  // solveIsland's contacts before it gathered again
  std::vector<double> islandReachSpeeds;           // and the speeds, by member, that set its reach
  // solveIsland's velocities and separateIsland's lists, kept so that a step's many solves do not
  // allocate (neither is called from within itself or the other's use of them).
  std::vector<Vec2> islandVelocities;
  // The accelerated sweeps' multipliers before a sweep and search direction (solveIsland).
  std::vector<double> islandPreviousImpulses, islandDirection;
  // islandScratch's contacts as the sweeps read them, packed and in wavefront order (island.cpp,
  // scheduleSweeps). 56 bytes: the sweeps stream them, a thousand times a step for a crowd's jam.
  struct SweepRow {
    int ka, kb;  // kb >= the member count: held fixed, its value at x[kb] (SweepSchedule::holders)
    Vec2 normal;
    double inverseA, inverseB;
    double target;
    double lambda;
  };
  struct SweepSchedule {
    std::vector<SweepRow> rows;          // in sweep order
    std::vector<Vec2> holders;           // the holder rows' velocities, in the order of their slots
    std::vector<uint32_t> contactAt;     // sweep position -> index into islandScratch
    std::vector<double> scale;           // the over-relaxed sweeps' omega / (inverseA + inverseB) by row
    std::vector<uint32_t> level, next;   // scratch: each row's level; each member's next level, then
                                         // each level's next position
  } sweepSchedule;
  /// Packs islandScratch's contacts (with their impulses) into sweepSchedule.rows in wavefront order.
  void scheduleSweeps(size_t memberCount);
  /// Copies the rows' impulses back into islandScratch.
  void unscheduleSweeps();
  struct SeparateScratch {
    std::vector<Vec2> displacements;
    std::vector<double> lower;
    std::vector<SweepRow> nearRows;  // the rows the sweeps look at (separateIsland)
    std::vector<uint32_t> leftOut;   // the positions of the others in the schedule
  } separateScratch;
  /// At a step's start when the sweeps stopped short (without gravity before separateIsland): stops the
  /// members whose velocities in v would close a contact more than kTrimSlack of its smaller radius
  /// beyond its gap within the h seconds left, and those that then would; under gravity only members a
  /// contact pushes (island.cpp).
  void trimIsland(const std::vector<uint32_t>& members, std::vector<Vec2>& v, double h);
  struct TrimScratch {
    std::vector<uint32_t> first, next;        // by member: where its contacts start in contactsOf
    std::vector<uint32_t> contactsOf, queue;  // contacts by member; the worklist
    std::vector<char> queued;                 // by contact
  } trimScratch;
  /// Without gravity, at a step's start: moves the members (advanced to the step's start, their
  /// velocities solved) apart where they overlap, without touching a velocity (island.cpp).
  void separateIsland(const std::vector<uint32_t>& members, const std::vector<Vec2>& v, double h);
  /// The exact projection of a few members' velocities (theirs before the solve) onto islandScratch's
  /// contacts: v and the contacts' impulses, or false when it fails (island.cpp).
  bool projectIslandExactly(const std::vector<uint32_t>& members, std::vector<Vec2>& v, double tolerance);
  struct ExactIslandScratch {
    std::vector<double> inverseMass, impulses;
    std::vector<detail::ProjectionRow> rows;
    std::vector<Vec2> velocities;
    detail::ProjectionScratch projection;
  } exactIslandScratch;  // projectIslandExactly's, kept so that a warm solve allocates nothing
  std::vector<std::pair<uint64_t, double>> islandImpulses, islandNext;  // warm start, by islandKey
  /// A pair whose contact an island solve holds: a stepped body and anything but a free body.
  static bool heldByIsland(const detail::BodySlot& a, const detail::BodySlot& b) {
    auto free = [](const detail::BodySlot& s) { return s.type == BodyType::Dynamic && !s.asleep && !s.stepped; };
    return (a.stepped && !free(b)) || (b.stepped && !free(a));
  }
  /// The stepped bodies within `hops` candidate pairs of the seeds, seeds first; hops < 0: all that a
  /// change of the seeds' motion can reach (their island). Into `members`, which it clears first.
  void islandOf(std::span<const uint32_t> seeds, int hops, std::vector<uint32_t>& members);
  std::vector<uint32_t> islandOf(std::span<const uint32_t> seeds) {
    std::vector<uint32_t> members;
    islandOf(seeds, -1, members);
    return members;
  }
  /// Makes free bodies stepped at `now`: the rest of the step's gravity as an impulse, straight paths.
  void joinIslands(std::span<const uint32_t> joining, double now, double dt);
  struct IslandSolve {
    int reported;  // contact events it reported
    bool met;      // its constraints hold (to the solve's tolerance)
  };
  /// Solves the contacts of `members` (stepped bodies; advanced to `now`) among themselves and against
  /// everything else but free bodies, held fixed on their paths, for the rest of the step. Reports as
  /// contact events the contacts that closed faster than `reportAbove`, and the contact of the fixture
  /// pair `reportPair` (islandKey), if they took an impulse, at most `maxReports`. `warmStart`: from the
  /// impulses of the last step's start (only at a step's start); `whole`: an island (more sweeps) rather
  /// than a part of one.
  IslandSolve solveIsland(const std::vector<uint32_t>& members, double now, double dt, double reportAbove,
                          uint64_t reportPair = ~uint64_t{0}, bool warmStart = false, bool whole = false,
                          int maxReports = std::numeric_limits<int>::max());
  // solveIsland's parts (island.cpp).
  double gatherIslandContacts(const std::vector<uint32_t>& members, double now, double h,
                              std::span<const double> reachSpeeds = {});
  /// The members' velocities after the solve over islandScratch's contacts, into v (true when it
  /// converged or came close enough); `speed` is the fastest at play, as gathered. `carried`: v and the
  /// contacts' impulses are where an earlier solve of the same members stopped, and it sweeps on.
  bool solveIslandVelocities(const std::vector<uint32_t>& members, std::vector<Vec2>& v, double speed, double h,
                             bool warmStart, bool whole, bool carried = false);
  /// Without gravity, after a solve of islandScratch's contacts that did not converge: a kinematic body
  /// pushing members that the rest of the island cannot let by (a gate shutting on a crowd that fills
  /// the gap between it and a wall: no velocities meet every contact) passes over them, as over a
  /// squeezed body. Each of its contacts that took an impulse has its pair of fixtures exempt from
  /// collisions until they no longer overlap (squeeze.h), and counts a squeeze; true if any did, and
  /// the caller gathers and solves again without them. Left to events, each member was squeezed in turn
  /// after its count of collisions, and the island's solves after each hit failed again.
  bool passKinematicOverPushed();
  /// Gives `after` (a wider gather of the same members at the same time) the impulses of the contacts
  /// of `before`, which it holds in the same order; false, and no impulses, when it does not hold them.
  static bool carryImpulses(const std::vector<IslandContact>& before, std::vector<IslandContact>& after);
  /// Adds to islandScratch a contact for each static Segment that a member's straight path along v crosses
  /// within h though no contact of the gather holds it (a bare Segment's end holds nothing); true if any.
  bool holdSegmentCrossings(const std::vector<uint32_t>& members, const std::vector<Vec2>& v, double now, double h);
  /// The members (their indices in the last gather's list, ascending) with a candidate pair with a static
  /// Segment (neither fixture a sensor): the only ones holdSegmentCrossings can hold.
  std::vector<uint32_t> islandSegmentMembers;
  std::vector<std::pair<uint32_t, uint32_t>> islandHeldSegments;  // its (member fixture, Segment) pairs
  /// `start`: the step's first solve, after which startIslands frees the members no contact pushed.
  void keepIslandEnergy(const std::vector<uint32_t>& members, std::vector<Vec2>& v, double h, bool start);
  std::vector<char> islandMemberHeld;  // keepIslandEnergy's marks, by member
  /// The sweeps over islandScratch's contacts, on the members' velocities v, at most maxIterations:
  /// over-relaxed by omega (true when they converged to `tolerance`), or, under gravity, accelerated
  /// (converged, or close enough to keep every contact within kCloseEnough of its radius, or stopped).
  bool sweepIsland(std::vector<Vec2>& v, double omega, double tolerance, int maxIterations);
  enum class SweepEnd { Converged, CloseEnough, Stopped };
  SweepEnd sweepIslandAccelerated(std::vector<Vec2>& v, double tolerance, double h, int maxIterations);
  /// By body, for stepped bodies: the energy its island's solves may still give back of what its straight
  /// path lost against the parabola it stands in for (keepIslandEnergy). Set when the path begins.
  std::vector<double> gravityAllowance;
  /// By body: a contact of an island solve pushed it this step (markHeld marks it after each solve; the
  /// start solve's trimIsland and then startIslands, which clears the stepped bodies' marks before that
  /// solve, read them). Sized by startIslands, which every hybrid step runs before any solve.
  std::vector<uint8_t> steppedHeld;
  void markHeld();
  int reportIslandContacts(double now, double reportAbove, uint64_t reportPair, int maxReports);
  /// Moves the seeds' part of their island after their motion changed at `now` (a hit, a join): the
  /// stepped bodies within `hops` pairs of them, or the whole island when that part cannot keep clear of
  /// the rest; predicts again every body whose motion changed. Returns the events it reported.
  int settleAround(std::span<const uint32_t> seeds, int hops, double now, double dt,
                   uint64_t reportPair = ~uint64_t{0});
  /// settleAround's lists, kept between calls so that a step's many settles do not allocate; one set
  /// for each level of settleAround's nesting (settleUnsolvedIslandPairs calls it again, once).
  struct SettleScratch {
    std::vector<uint32_t> members;
    std::vector<Vec2> before;
    std::vector<uint32_t> counts;
    std::vector<detail::LastContact> lasts;
    std::vector<double> allowances;
  };
  std::vector<SettleScratch> settleScratch;
  size_t settleDepth = 0;
  /// Bodies whose broad-phase query (the hybrid step's repredict) found a contact an island holds after their island's
  /// solve; settleUnsolvedIslandPairs solves them again.
  std::vector<uint32_t> unsolvedIslandPairs, unsolvedSeeds;
  bool settlingUnsolved = false;
  void settleUnsolvedIslandPairs(double now, double dt);
  /// The start of a hybrid step, after the sweep: gravity and the solve for every stepped body; a
  /// stepped body that nothing holds is free again at once (returned in `freed`).
  void startIslands(double dt, std::vector<uint32_t>& freed);
  /// The end of a hybrid step (`end`: where the bodies stop): stepped bodies at rest sleep, bottom up.
  void endIslands(double end);


  // jam.cpp: a cluster of touching bodies resolved at once when one of them collides too often.
  static constexpr int kJamCollisions = 64;
  std::vector<int> jamSlot;  // scratch of settleJam, all -1 between calls
  uint32_t jamCounter = 0;   // numbers the jams, so that two clusters settled at one instant differ
  /// The jam that last settled a body in this step (jamCounter) and when, in step time.
  struct JamMark {
    double time = -1;  // < 0: none this step (kJamRefused: refused)
    uint32_t jam = 0;
    bool operator==(const JamMark&) const = default;
  };
  /// Its mark, by body index: none for a body no jam marked this step.
  JamMark jamMarkOf(uint32_t body) const { return jamMarks_.get(body); }
  /// Whether a jam settled this pair's contact at this very instant: both dynamic bodies were in it (or
  /// the other one was held fixed), so any approach left between them is the solve's round-off.
  bool settledTogether(uint32_t a, uint32_t b, double now) const;
  /// Counts a collision of `body` at `now` in this step of dt; true once it has had more than
  /// kJamCollisions.
  bool isJammed(uint32_t body, double now, double dt);
  /// Without gravity, a body past kBurstStart collisions in the step whose last kJamCollisions came each
  /// within kBurstWindow of the step of the one before is in an inelastic collapse at (nearly) one
  /// instant, and jams as a driven body does (isJammed). Counts the collision at `now`.
  bool collapsing(uint32_t body, double now, double dt);
  static constexpr int kBurstStart = 16;
  static constexpr double kBurstWindow = 1e-4;
  /// Whether `body` may join a jam at `now` at all: dynamic, awake, held by island contacts
  /// (heldByIslandContacts), not refused this step, and resting on (WorldDef::restingSpeed > 0).
  bool canJam(uint32_t body, double now) const;
  bool mayJam(uint32_t body) const;
  bool bodyIsPoint(const BodySlot& b) const;
  /// Whether an island's contacts, built from distances, can hold `body` at `now`: it is no point, and
  /// no circle of it has its centre on a static fixture's boundary (a circle made over a wall's face),
  /// where a distance tells no side.
  bool heldByIslandContacts(uint32_t body, double now) const;
  /// Brings the touching cluster of `seed` into the stepped islands at `now` and solves its island;
  /// returns the contact events it took (at least 1, at most `budget` >= 1), or
  /// returns 0 when it is refused (below).
  int settleJam(uint32_t seed, double now, double dt, int budget);
  /// JamMark::time of a body whose jam was refused this step (no jam is tried for it again).
  static constexpr double kJamRefused = -2;
  /// Without gravity, the overlap a jam's solve may add within the step, in radii.
  static constexpr double kJamResidual = 0.01;
  void refuseJam(const std::vector<uint32_t>& cluster);
  /// How much further than at the solve's start the last solve's contacts (islandScratch) overlap after
  /// h more seconds on the bodies' velocities, beyond kJamResidual of the radius: <= 0 when none does.
  double islandResidual(double h) const;
  /// Counts the contact's collision for both bodies; when one of them is jammed, settles its cluster
  /// (counting its events against the step's budget, which must have room for one) and returns true.
  /// caughtA and caughtB say that the contact's first or second body is caught absorbing round-off
  /// approaches at one instant (HybridStep::dismissContact): it is jammed whatever its count.
  bool settleJamAt(const detail::PredictedContact& c, double dt, bool caughtA = false, bool caughtB = false);

  /// Whether islandNext is the next step's warm start: no fixture was destroyed since it was kept
  /// (beginStep drops it otherwise, as indices are reused).
  bool warmStartKept() const { return w.changes.fixtureRemovals == fixtureRemovalsSeen_; }

 private:
  // beginStep's: the jams' numbering at the step's start, whether startIslands has made islandNext the
  // warm start since, and the world's count of destroyed fixtures when the warm start was last kept
  // (it is kept by fixture index, and indices are reused).
  uint32_t jamCounterAtStart_ = 0;
  bool swapped_ = false;
  uint64_t fixtureRemovalsSeen_ = 0;
  BodyMarks<JamMark> jamMarks_;  // cleared by beginStep
  // collapsing's run of collisions close together, by body: the last one's instant and how many.
  struct Burst {
    double time = -1;
    uint32_t count = 0;
    bool operator==(const Burst&) const = default;
  };
  BodyMarks<Burst> bursts_;  // cleared by beginStep
};

}  // namespace rattle::detail
