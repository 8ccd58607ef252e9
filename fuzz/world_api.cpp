// Fuzz target: rattle::World driven through the public API by a byte program.
//
// The first byte picks the mode (Hybrid, Discrete, Predictive) and whether there is gravity; the rest
// is a sequence of calls: create bodies of every type and fixtures of every geometry (sensors and
// filters too), closed static containers filled with disks, destroy, set, step and query. Values are
// sane most of the time (positions within 100, radii 0.05..5, speeds up to 50) and sometimes extreme
// (0, -0, tiny, huge, inf, nan, negative) so that validation is exercised. A call that is refused with
// rattle::Error is fine; any other exception, a crash or a sanitizer report is a finding. The work per
// input is bounded (kMaxBodies, kMaxCalls, kMaxSteps, WorldDef::maxEventsPerStep, and kWorkBudget over
// the steps' own counts of their work) so that one input runs well under libFuzzer's -timeout in the fuzz
// build.
//
// After every step the invariants below are checked; a violation aborts with a line that names its
// class, the body and the values:
//   finite   every body's position and velocity is finite;
//   inside   a dynamic body's centre that was not inside a static polygon before the step (that it
//            collides with), or inside within the tolerance where the last step left it, is not inside
//            it after the step by more than 1% of its radius + 1e-9 (a centre made or set inside one
//            has no side to be held to: README, Geometry);
//   escape   a disk that was created inside a closed static container (and was not moved by
//            setPosition or given other fixtures or filters since) has its centre inside it, to the same
//            tolerance; inside and escape hold a disk while its radius is in the documented range where
//            it is (inRange), and escape holds a point only in a container whose corners collide (not
//            in one of four bare Segments: README, Geometry);
//   energy   with no moving kinematic body, kinetic energy (plus gravity's potential energy) does not grow
//            over a step by more than 1e-12 of the energies at play (under gravity, plus what
//            WorldDef::restingSpeed may give each contact of the step, by design; the discrete mode is
//            held to it without gravity only, as its push-apart lifts bodies against gravity; under
//            gravity it is checked on steps of at most kLongestGravityStep, the bound the README gives);
//   events   contact and sensor events name live fixtures and bodies, or ones destroyed since the last
//            step; their times lie in [0, dt], normals are unit, impulses finite and >= 0; no step
//            processes more than WorldDef::maxEventsPerStep events;
//   budget   no step reaches WorldDef::maxEventsPerStep (kEventBudget): a class of its own, since piles
//            in the predictive mode may reach it today; checked when every speed is at most kBudgetSpeed
//            at the step's start (a disk at 1e9 units/s in a small box needs more events than any budget);
//   error    a step with a valid dt (finite, >= 0) throws rattle::Error, or one with an invalid dt does not;
//   query    queries return live fixtures, sorted, with ray fractions in [0, 1];
//   save     World::load takes the world's save, and the loaded world saves the same bytes; at the end
//            of the program, two worlds loaded from the last save step alike, bit for bit, for
//            kLoadedSteps steps of the last valid dt, at most kLongestGravityStep (README, "Saving a
//            world": lockstep peers rely on it).
// The discrete mode is held to inside and escape in steps where every body's own travel is less than its
// radius, the bound it documents (a faster body may pass a wall: README).
// A moving kinematic body may crush a disk into a wall, which no engine can prevent: during a step in
// which one moves, the inside and energy checks are skipped and containers its swept box reaches are
// forgotten. The inside, escape and energy checks apply within kTracked of the origin (see there).
//
// RATTLE_WORLD_API_REPORT lists classes that are reported instead of failing: the first violation of
// each in an input prints one line, "rattle fuzz report: ...", with the input in base64, and the input
// runs on. CI reports the budget class this way (.ci/run, fuzz/README.md).
// For triage only, RATTLE_WORLD_API_OFF lists classes not to check (comma-separated, e.g.
// "escape,budget"), and RATTLE_WORLD_API_MODES the modes to run (e.g. "hybrid,predictive"; inputs for
// other modes return at once); "extreme" in RATTLE_WORLD_API_OFF makes no extreme values, and
// "gravity-energy" leaves out the energy check under gravity only. Unset, everything is checked in every
// mode. RATTLE_WORLD_API_VERBOSE prints what each input does (calls, bodies after each step, the
// step's first contact events), for writing reproducers. fuzz/README.md says more.
#include <rattle/rattle.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace {

using rattle::BodyId;
using rattle::BodyType;
using rattle::Box;
using rattle::FixtureId;
using rattle::Vec2;

constexpr int kMaxBodies = 64;
constexpr int kMaxCalls = 200;
constexpr int kMaxSteps = 20;
// Steps each of two worlds loaded from the program's last save takes (the save check).
constexpr int kLoadedSteps = 3;
constexpr int kEventBudget = 20000;
constexpr double kEnergyTolerance = 1e-12;
// Under gravity the islands take a step's gravity as one impulse, and on longer steps that accounting can
// let energy grow (README, stepped islands): energy under gravity is checked on steps up to this long.
constexpr double kLongestGravityStep = 0.1;
constexpr double kGravity = -9.81;
// A disk counts as made inside a container only this far clear of its walls: one made touching a wall
// (or a point made on it) may be on either side of it by round-off.
constexpr double kInsideMargin = 1e-6;
// The geometric checks (inside, escape) and energy hold where coordinates resolve their tolerances: a box
// 4 wide at y = 1e308 is not a box in doubles. Farther out, only crashes, non-finite states, events and
// the budget count.
constexpr double kTracked = 1e6;

constexpr double kBudgetSpeed = 1000;

// The work an input's steps may do, in time-of-impact tests, a contact row swept counting as
// 1 / kRowsPerTest of one (the two cost about that in the release build; StepStats): once past it, the
// program ends after that step. Events alone do not bound a step's work. Under gravity a pile stepped a
// whole second at a time (a valid extreme dt is 1 s; the README asks for 0.1 s at most) solves thousands
// of speculative contacts per solve: one such step of 64 landing disks swept 21 million rows (0.4 s in
// the release build, 2.4 s in the fuzz build), and a few of them with the save check's ran past
// libFuzzer's timeout (every input a local run found past 3 s; a CI run at 7899866 stopped at 10 s).
// The budget is 0.1 to 0.3 s of the release build, three times what the seeds and kept inputs need
// (bench/README.md, "Piles").
constexpr long long kWorkBudget = 100000;
constexpr long long kRowsPerTest = 200;

bool tracked(Vec2 p) { return std::abs(p.x) <= kTracked && std::abs(p.y) <= kTracked; }

enum Check : unsigned {
  kFinite = 1u << 0,
  kInside = 1u << 1,
  kEscape = 1u << 2,
  kEnergy = 1u << 3,
  kEvents = 1u << 4,
  kBudget = 1u << 5,
  kStepError = 1u << 6,
  kQuery = 1u << 7,
  kExtreme = 1u << 8,  // not a check: off, the program never makes extreme values (triage only)
  kGravityEnergy = 1u << 9,  // energy under gravity, a part of kEnergy
  kSave = 1u << 10,
};

struct CheckName {
  const char* name;
  unsigned bit;
};
constexpr CheckName kCheckNames[] = {{"finite", kFinite}, {"inside", kInside}, {"escape", kEscape},
                                     {"energy", kEnergy}, {"events", kEvents}, {"budget", kBudget},
                                     {"error", kStepError}, {"query", kQuery},
                                     {"extreme", kExtreme}, {"gravity-energy", kGravityEnergy},
                                     {"save", kSave}};

bool listed(const char* list, const char* word) {
  const size_t n = std::strlen(word);
  for (const char* p = list; (p = std::strstr(p, word)) != nullptr; p += n) {
    const bool starts = p == list || p[-1] == ',';
    const bool ends = p[n] == '\0' || p[n] == ',';
    if (starts && ends) return true;
  }
  return false;
}

// Read once: the environment is the same for every input of a run.
unsigned enabledChecks() {
  static const unsigned enabled = [] {
    unsigned bits = ~0u;
    if (const char* off = std::getenv("RATTLE_WORLD_API_OFF"))
      for (const CheckName& c : kCheckNames)
        if (listed(off, c.name)) bits &= ~c.bit;
    return bits;
  }();
  return enabled;
}

unsigned reportedChecks() {
  static const unsigned reported = [] {
    unsigned bits = 0;
    if (const char* list = std::getenv("RATTLE_WORLD_API_REPORT"))
      for (const CheckName& c : kCheckNames)
        if (listed(list, c.name)) bits |= c.bit;
    return bits;
  }();
  return reported;
}

bool modeEnabled(rattle::StepMode mode) {
  static const char* modes = std::getenv("RATTLE_WORLD_API_MODES");
  if (modes == nullptr || *modes == '\0') return true;
  const char* name = mode == rattle::StepMode::Hybrid ? "hybrid" : mode == rattle::StepMode::Discrete ? "discrete" : "predictive";
  return listed(modes, name);
}

const char* modeName(rattle::StepMode mode) {
  return mode == rattle::StepMode::Hybrid ? "hybrid" : mode == rattle::StepMode::Discrete ? "discrete" : "predictive";
}

// The step being checked, for the message of a finding.
struct Where {
  rattle::StepMode mode = rattle::StepMode::Hybrid;
  bool gravity = false;
  int step = 0;
  double dt = 0;
} where;

// The input being run, for a report.
struct Input {
  const uint8_t* data = nullptr;
  size_t size = 0;
  unsigned reported = 0;  // the classes already reported for it
} input;

std::string base64(const uint8_t* data, size_t size) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < size; i += 3) {
    const uint32_t n = (uint32_t{data[i]} << 16) | (i + 1 < size ? uint32_t{data[i + 1]} << 8 : 0) |
                       (i + 2 < size ? uint32_t{data[i + 2]} : 0);
    out += digits[(n >> 18) & 63];
    out += digits[(n >> 12) & 63];
    out += i + 1 < size ? digits[(n >> 6) & 63] : '=';
    out += i + 2 < size ? digits[n & 63] : '=';
  }
  return out;
}

// "<lead> world_api invariant '<check>' (<where>): <the message>", without an end of line.
void describeViolation(const char* lead, const char* check, const char* format, va_list args) {
  std::fprintf(stderr, "%s world_api invariant '%s' (%s mode, gravity %s, step %d, dt %.17g): ", lead, check,
               modeName(where.mode), where.gravity ? "on" : "off", where.step, where.dt);
  std::vfprintf(stderr, format, args);
}

// A violation of a class in RATTLE_WORLD_API_REPORT: one line for the first in an input, and on.
void report(unsigned bit, const char* check, const char* format, ...) {
  if (input.reported & bit) return;
  input.reported |= bit;
  va_list args;
  va_start(args, format);
  describeViolation("rattle fuzz report:", check, format, args);
  va_end(args);
  std::fprintf(stderr, "; input (base64, %zu bytes): %s\n", input.size, base64(input.data, input.size).c_str());
}

[[noreturn]] void finding(const char* check, const char* format, ...) {
  va_list args;
  va_start(args, format);
  describeViolation("\nrattle fuzz check failed:", check, format, args);
  va_end(args);
  std::fprintf(stderr, "\n");
  std::abort();
}

// The program's bytes. Past the end every read gives 0, and the program ends at the next call.
class Reader {
 public:
  Reader(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  bool done() const { return at_ >= size_; }
  uint8_t u8() { return at_ < size_ ? data_[at_++] : 0; }

  // A value in [lo, hi] from two bytes, or (first byte >= 0xF8, 1 in 32) one of the extremes.
  double real(double lo, double hi) {
    const unsigned first = u8();
    if (first >= 0xF8 && (enabledChecks() & kExtreme)) return extreme();
    if (first >= 0xF8) return lo + (hi - lo) * (u8() / 255.0);
    const unsigned v = first * 256u + u8();
    return lo + (hi - lo) * (static_cast<double>(v) / (0xF8 * 256.0 - 1.0));
  }
  Vec2 vec(double lo, double hi) {
    const double x = real(lo, hi);
    return {x, real(lo, hi)};
  }
  double extreme() {
    static constexpr double kExtremes[] = {0.0,
                                           -0.0,
                                           1e-300,
                                           -1e-12,
                                           1e300,
                                           -1e300,
                                           std::numeric_limits<double>::infinity(),
                                           -std::numeric_limits<double>::infinity(),
                                           std::numeric_limits<double>::quiet_NaN(),
                                           1e9,
                                           -1e9,
                                           std::numeric_limits<double>::denorm_min(),
                                           std::numeric_limits<double>::max(),
                                           -1.0,
                                           1.5,
                                           1e-12};
    return kExtremes[u8() % std::size(kExtremes)];
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t at_ = 0;
};

bool collide(const rattle::Filter& a, const rattle::Filter& b) {
  if ((a.categoryBits & b.maskBits) == 0 || (b.categoryBits & a.maskBits) == 0) return false;
  return a.group == 0 || a.group != b.group;
}

bool inBox(const Box& box, Vec2 p, double margin) {
  return p.x >= box.min.x - margin && p.x <= box.max.x + margin && p.y >= box.min.y - margin && p.y <= box.max.y + margin;
}

// The part of a dynamic body that collides: the centre its circles share, the largest radius, the filter
// of that fixture. Points count as circles of radius 0.
struct Disk {
  BodyId body;
  Vec2 centre;
  double radius = 0;
  rattle::Filter filter;
};

// A disk's radius is 0 or at least World::kMinRelativeRadius x max(1, |x|, |y|) where it was made, and it
// is held to the geometric checks only while that stays so (README, "Ranges"): a disk of radius 1e-12 made
// at the origin that slid along a wall at x = -3 went 0.04 into it
// (fuzz/regressions/world_api/inside-hybrid-tiny-disk-beyond-its-range).
bool inRange(const Disk& d) {
  return d.radius == 0 ||
         d.radius >= rattle::World::kMinRelativeRadius * std::max({1.0, std::abs(d.centre.x), std::abs(d.centre.y)});
}

std::optional<Disk> diskOf(const rattle::World& world, BodyId body) {
  std::optional<Disk> disk;
  const Vec2 p = world.position(body);
  for (FixtureId f : world.fixtures(body)) {
    if (world.isSensor(f)) continue;
    const rattle::Geometry& g = world.geometry(f);
    Vec2 offset;
    double r = 0;
    if (const auto* c = std::get_if<rattle::Circle>(&g)) {
      offset = c->center;
      r = c->radius;
    } else if (const auto* q = std::get_if<rattle::Point>(&g)) {
      offset = q->position;
    } else {
      continue;
    }
    if (!disk || r > disk->radius) disk = Disk{body, p + offset, r, world.filter(f)};
  }
  return disk;
}

// How deep a point is inside a placed counter-clockwise polygon (<= 0: outside or on it).
double depthInside(const rattle::Polygon& polygon, Vec2 position, Vec2 point) {
  double depth = std::numeric_limits<double>::infinity();
  const size_t n = polygon.points.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = polygon.points[i] + position;
    const Vec2 e = polygon.points[(i + 1) % n] - polygon.points[i];
    const double len = rattle::length(e);
    if (!(len > 0)) return 0;
    const double outside = rattle::cross(e, point - a) / -len;  // > 0 on the outer side of a CCW edge
    depth = std::min(depth, -outside);
  }
  return depth;
}

double tolerance(double radius) { return 0.01 * radius + 1e-9; }

struct Container {
  BodyId wall;
  std::vector<FixtureId> walls;
  Box inner;  // where the disks are
  Box outer;  // the walls' outer faces
  std::vector<BodyId> members;
  bool live = true;
  // Four bare Segments meet at ends, which do not collide (README, Geometry): a point sliding along one
  // wall into a corner meets the next wall exactly at its end and passes. Disks touch a wall at a radius
  // from the corner, inside it.
  bool holdsPoints = true;
};

class Program {
 public:
  Program(Reader& in, rattle::World& world) : in_(in), world_(world) {}

  void run() {
    int calls = 0;
    while (!in_.done() && calls < kMaxCalls && steps_ < kMaxSteps && work_ < kWorkBudget) {
      ++calls;
      const uint8_t op = in_.u8();
      try {
        call(op % 16);
      } catch (const rattle::Error& e) {
        // Refused: the world is unchanged (types.h), so the bookkeeping must not have changed either;
        // every call below updates it only after the world accepted the call.
        ++refused_;
        if (verbose()) std::fprintf(stderr, "world_api: call %d (op %d) refused: %s\n", calls, op % 16, e.what());
      }
    }
    if (enabledChecks() & kSave) checkLoadsStepAlike();
    if (verbose())
      std::fprintf(stderr,
                   "world_api: %s mode, gravity %s: %d calls (%d refused), %d steps, %d live bodies, %zu containers, "
                   "work %lld of %lld\n",
                   modeName(where.mode), where.gravity ? "on" : "off", calls, refused_, steps_, world_.bodyCount(),
                   containers_.size(), work_, kWorkBudget);
  }

  // RATTLE_WORLD_API_VERBOSE=1: what each input did, on stderr (for reading a reproducer, not for fuzzing).
  static bool verbose() {
    static const bool on = std::getenv("RATTLE_WORLD_API_VERBOSE") != nullptr;
    return on;
  }

 private:
  Reader& in_;
  rattle::World& world_;
  std::vector<BodyId> bodies_;  // every body made, live or not: stale handles are used too
  std::vector<FixtureId> fixtures_;
  std::vector<Container> containers_;
  std::vector<BodyId> destroyedBodies_;  // since the last step
  std::vector<FixtureId> destroyedFixtures_;
  std::vector<FixtureId> described_;  // verbose: fixtures already printed in full
  int created_ = 0;
  int steps_ = 0;
  int refused_ = 0;
  long long work_ = 0;  // of the steps so far (kWorkBudget)
  double lastValidDt_ = 1.0 / 60;  // of the last step that took a valid dt (checkLoadsStepAlike)

  bool gravity() const { return world_.definition().gravity.y != 0; }

  BodyId anyBody() {
    if (bodies_.empty()) return BodyId{in_.u8(), in_.u8()};
    return bodies_[in_.u8() % bodies_.size()];
  }
  FixtureId anyFixture() {
    if (fixtures_.empty()) return FixtureId{in_.u8(), in_.u8()};
    return fixtures_[in_.u8() % fixtures_.size()];
  }

  rattle::Filter filter() {
    const uint8_t kind = in_.u8();
    if (kind < 192) return {};
    rattle::Filter f;
    f.categoryBits = 1u << (in_.u8() % 4);
    f.maskBits = kind & 1 ? 0xFFFFFFFFu : in_.u8();
    f.group = static_cast<int32_t>(in_.u8() % 3) - 1;
    return f;
  }

  rattle::Geometry geometry(int type) {
    switch (type) {
      case 0:
        return rattle::Point{in_.vec(-5, 5)};
      case 1: {
        const Vec2 c = in_.u8() < 192 ? Vec2{} : in_.vec(-5, 5);
        return rattle::Circle{c, in_.real(0.05, 5)};
      }
      case 2: {
        const Vec2 a = in_.vec(-20, 20);
        return rattle::Segment{a, in_.vec(-20, 20)};
      }
      case 3: {
        rattle::Polyline line;
        const int n = 2 + in_.u8() % 5;
        for (int i = 0; i < n; ++i) line.points.push_back(in_.vec(-20, 20));
        return line;
      }
      default: {
        // Convex most of the time: a rectangle or a regular polygon; now and then arbitrary points.
        rattle::Polygon polygon;
        const uint8_t kind = in_.u8() % 4;
        const Vec2 c = in_.vec(-10, 10);
        if (kind == 0) {
          const double w = in_.real(0.05, 10), h = in_.real(0.05, 10);
          polygon.points = {c, c + Vec2{w, 0}, c + Vec2{w, h}, c + Vec2{0, h}};
        } else if (kind == 1) {
          const int n = 3 + in_.u8() % 6;
          for (int i = 0; i < n; ++i) polygon.points.push_back(in_.vec(-10, 10));
        } else {
          const int n = 3 + in_.u8() % 6;
          const double r = in_.real(0.05, 10), phase = in_.real(0, 6.3);
          for (int i = 0; i < n; ++i) {
            const double a = phase + 2 * std::numbers::pi * i / n;
            polygon.points.push_back(c + Vec2{r * std::cos(a), r * std::sin(a)});
          }
        }
        return polygon;
      }
    }
  }

  void call(int op) {
    switch (op) {
      case 0:
      case 1:
        return createDisk();
      case 2:
        return createBody();
      case 3:
        return createFixture();
      case 4:
        return createContainer();
      case 5:
        return destroyBody(anyBody());
      case 6:
        return destroyFixture(anyFixture());
      case 7: {
        const BodyId b = anyBody();
        world_.setPosition(b, in_.vec(-100, 100));
        return changedFixtureOf(b);  // a moved disk is no longer known to be inside; moved walls open a box
      }
      case 8: {
        const BodyId b = anyBody();
        return world_.setVelocity(b, in_.vec(-50, 50));
      }
      case 9: {
        const FixtureId f = anyFixture();
        return world_.setDensity(f, in_.real(0.1, 10));
      }
      case 10: {
        const FixtureId f = anyFixture();
        return world_.setRestitution(f, in_.real(0, 1));
      }
      case 11: {
        const FixtureId f = anyFixture();
        world_.setFilter(f, filter());
        return changedFixtureOf(world_.body(f));
      }
      case 12:
      case 13:
        return step();
      case 14:
        return query();
      default:
        return look();
    }
  }

  void createDisk() {
    if (created_ >= kMaxBodies) return;
    ++created_;
    const Vec2 p = in_.vec(-100, 100);
    const Vec2 v = in_.vec(-50, 50);
    const double r = in_.real(0.05, 5);
    const double restitution = in_.real(0, 1);
    const double density = in_.u8() < 224 ? 1.0 : in_.real(0.1, 10);
    const rattle::Filter f = filter();
    const BodyId b = world_.createBody({.type = BodyType::Dynamic, .position = p, .velocity = v});
    bodies_.push_back(b);
    const FixtureId fx = world_.createFixture(
        b, {.geometry = rattle::Circle{{}, r}, .density = density, .restitution = restitution, .filter = f});
    fixtures_.push_back(fx);
    for (Container& c : containers_)
      if (c.live && wallsMeet(c, f) && inBox(c.inner, p, -(r + kInsideMargin))) c.members.push_back(b);
  }

  void createBody() {
    if (created_ >= kMaxBodies) return;
    ++created_;
    const BodyType type = static_cast<BodyType>(in_.u8() % 3);
    const Vec2 p = in_.vec(-100, 100);
    const Vec2 v = type == BodyType::Static && in_.u8() < 240 ? Vec2{} : in_.vec(-50, 50);
    bodies_.push_back(world_.createBody({.type = type, .position = p, .velocity = v, .userData = bodies_.size()}));
  }

  void createFixture() {
    const BodyId b = anyBody();
    const uint8_t type = in_.u8();
    const rattle::Geometry g = geometry(type % 5);
    rattle::FixtureDef def{.geometry = g};
    def.density = in_.u8() < 224 ? 1.0 : in_.real(0.1, 10);
    def.restitution = in_.real(0, 1);
    def.sensor = (type & 0x20) != 0;
    def.filter = filter();
    fixtures_.push_back(world_.createFixture(b, def));
    changedFixtureOf(b);
  }

  bool wallsMeet(const Container& c, const rattle::Filter& f) const {
    for (FixtureId w : c.walls)
      if (!collide(world_.filter(w), f)) return false;
    return true;
  }

  // A closed static box (a Polyline, four Segments or a ring of four Polygons) with up to 16 disks in a
  // grid inside it, moving in random directions.
  void createContainer() {
    if (created_ >= kMaxBodies) return;
    const uint8_t kind = in_.u8() % 3;
    const Vec2 c = in_.vec(-50, 50);
    const double hx = in_.real(1, 20), hy = in_.real(1, 20);
    const int count = in_.u8() % 17;
    const double r = in_.real(0.05, 1);
    const double speed = in_.real(0, 50);
    const double restitution = in_.real(0, 1);
    const BodyId wall = world_.createBody({.type = BodyType::Static, .position = c});
    ++created_;
    bodies_.push_back(wall);
    Container box{.wall = wall, .inner = {c - Vec2{hx, hy}, c + Vec2{hx, hy}}, .outer = {}, .holdsPoints = kind != 1};
    box.outer = box.inner;
    const Vec2 k[4] = {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}};
    std::vector<rattle::Geometry> shapes;
    if (kind == 0) {
      shapes.push_back(rattle::Polyline{{k[0], k[1], k[2], k[3], k[0]}});
    } else if (kind == 1) {
      for (int i = 0; i < 4; ++i) shapes.push_back(rattle::Segment{k[i], k[(i + 1) % 4]});
    } else {
      const double t = 0.5;
      shapes.push_back(rattle::Polygon{{{-hx - t, -hy - t}, {hx + t, -hy - t}, {hx + t, -hy}, {-hx - t, -hy}}});
      shapes.push_back(rattle::Polygon{{{-hx - t, hy}, {hx + t, hy}, {hx + t, hy + t}, {-hx - t, hy + t}}});
      shapes.push_back(rattle::Polygon{{{-hx - t, -hy}, {-hx, -hy}, {-hx, hy}, {-hx - t, hy}}});
      shapes.push_back(rattle::Polygon{{{hx, -hy}, {hx + t, -hy}, {hx + t, hy}, {hx, hy}}});
      box.outer = {box.inner.min - Vec2{t, t}, box.inner.max + Vec2{t, t}};
    }
    for (const rattle::Geometry& g : shapes) {
      box.walls.push_back(world_.createFixture(wall, {.geometry = g}));
      fixtures_.push_back(box.walls.back());
    }
    if (!tracked(box.outer.min) || !tracked(box.outer.max)) box.live = false;
    containers_.push_back(box);
    // Extreme sizes give no grid (and no float-to-int conversion out of range).
    const double spacing = std::max(3 * r, 0.2);
    const double across = std::floor(2 * hx / spacing), up = std::floor(2 * hy / spacing);
    const int columns = across >= 1 ? static_cast<int>(std::min(across, 64.0)) : 0;
    const int rows = up >= 1 ? static_cast<int>(std::min(up, 64.0)) : 0;
    for (int i = 0; i < count && i < columns * rows && created_ < kMaxBodies; ++i) {
      const Vec2 p = box.inner.min + Vec2{spacing * (0.5 + i % columns), spacing * (0.5 + i / columns)};
      const double angle = 2 * std::numbers::pi * in_.u8() / 256.0;
      const double s = speed * in_.u8() / 255.0;
      const BodyId b = world_.createBody({.type = BodyType::Dynamic, .position = p, .velocity = {s * std::cos(angle), s * std::sin(angle)}});
      ++created_;
      bodies_.push_back(b);
      fixtures_.push_back(world_.createFixture(b, {.geometry = rattle::Circle{{}, r}, .restitution = restitution}));
      containers_.back().members.push_back(b);
    }
  }

  void forgetMember(BodyId b) {
    for (Container& c : containers_) std::erase(c.members, b);
  }

  // A body whose fixtures changed: a disk may now reach through a wall (a larger circle, another
  // filter); a container whose walls changed may be open.
  void changedFixtureOf(BodyId b) {
    forgetMember(b);
    for (Container& c : containers_)
      if (c.wall == b) c.live = false;
  }

  void destroyBody(BodyId b) {
    const std::vector<FixtureId> gone = world_.fixtures(b);
    world_.destroyBody(b);
    destroyedBodies_.push_back(b);
    destroyedFixtures_.insert(destroyedFixtures_.end(), gone.begin(), gone.end());
    changedFixtureOf(b);
  }

  void destroyFixture(FixtureId f) {
    const BodyId b = world_.body(f);
    world_.destroyFixture(f);
    destroyedFixtures_.push_back(f);
    changedFixtureOf(b);
  }

  std::vector<BodyId> live(BodyType type) const {
    std::vector<BodyId> out;
    for (BodyId b : bodies_)
      if (world_.isValid(b) && world_.type(b) == type) out.push_back(b);
    return out;
  }

  // The swept boxes of the kinematic bodies that move during a step of dt and have physical fixtures.
  std::vector<Box> movingKinematics(double dt) const {
    std::vector<Box> boxes;
    for (BodyId b : live(BodyType::Kinematic)) {
      const Vec2 v = world_.velocity(b);
      if (v.x == 0 && v.y == 0) continue;
      const Vec2 p = world_.position(b);
      for (FixtureId f : world_.fixtures(b)) {
        if (world_.isSensor(f)) continue;
        const Box box = rattle::boxOf(world_.geometry(f));
        boxes.push_back(rattle::unionOf(box.translated(p), box.translated(p + dt * v)));
      }
    }
    return boxes;
  }

  struct Energy {
    double total = 0;
    double scale = 0;  // the energies at play, for the relative tolerance
    double maxMass = 0;
    bool tracked = true;  // every dynamic body within kTracked of the origin
  };

  Energy energy() const {
    Energy e;
    const double g = world_.definition().gravity.y;
    for (BodyId b : live(BodyType::Dynamic)) {
      const double m = world_.mass(b);
      const Vec2 v = world_.velocity(b);
      const double y = world_.position(b).y;
      const double kinetic = 0.5 * m * rattle::dot(v, v);
      e.total += kinetic - m * g * y;
      e.scale += kinetic + std::abs(m * g * y);
      e.maxMass = std::max(e.maxMass, m);
      e.tracked = e.tracked && tracked(world_.position(b));
    }
    return e;
  }

  // (disk, polygon fixture) pairs where the disk's centre is not inside the polygon.
  struct Outside {
    BodyId disk;
    FixtureId polygon;
  };
  // The pairs the last step held to the inside check, with where it left the disk and the wall.
  struct HeldAtEnd {
    BodyId disk;
    FixtureId polygon;
    Vec2 diskAt, wallAt;
  };
  std::vector<HeldAtEnd> heldAtEnd_;

  bool heldWhereLeft(BodyId disk, FixtureId polygon, BodyId wall) const {
    const Vec2 d = world_.position(disk), w = world_.position(wall);
    return std::any_of(heldAtEnd_.begin(), heldAtEnd_.end(), [&](const HeldAtEnd& h) {
      return h.disk == disk && h.polygon == polygon && h.diskAt.x == d.x && h.diskAt.y == d.y && h.wallAt.x == w.x &&
             h.wallAt.y == w.y;
    });
  }

  std::vector<Outside> outsidePolygons() const {
    std::vector<Outside> out;
    const std::vector<BodyId> walls = live(BodyType::Static);
    for (BodyId b : live(BodyType::Dynamic)) {
      const std::optional<Disk> d = diskOf(world_, b);
      if (!d || !inRange(*d)) continue;
      for (BodyId w : walls) {
        for (FixtureId f : world_.fixtures(w)) {
          const auto* polygon = std::get_if<rattle::Polygon>(&world_.geometry(f));
          if (polygon == nullptr || world_.isSensor(f) || !collide(world_.filter(f), d->filter)) continue;
          if (!tracked(d->centre) || !tracked(world_.position(w))) continue;
          // A centre inside a polygon (made or set there, or a polygon made around it) has no side to be
          // held to and moves on freely (README, Geometry). So a centre is held when it is outside at the
          // step's start, or inside within the tolerance where the last step left it.
          const double depth = depthInside(*polygon, world_.position(w), d->centre);
          if (depth < 0 || (depth <= tolerance(d->radius) && heldWhereLeft(b, f, w))) out.push_back({b, f});
        }
      }
    }
    return out;
  }

  static double pickDt(Reader& in) {
    static constexpr double kDts[] = {0, 1.0 / 240, 1.0 / 120, 1.0 / 60, 1.0 / 60, 1.0 / 30, 0.05, 0.1};
    const uint8_t b = in.u8();
    if (b >= 0xF8) {
      const double e = in.extreme();
      // Valid extremes (huge, 1e9) would only run into the event budget: keep the refused ones and zeros.
      return std::isfinite(e) && e > 1 ? 1.0 : e;
    }
    return kDts[b % std::size(kDts)];
  }

  void step() {
    const double dt = pickDt(in_);
    const bool valid = std::isfinite(dt) && dt >= 0;
    const unsigned checks = enabledChecks();
    const std::vector<Box> kinematics = valid ? movingKinematics(dt) : std::vector<Box>{};
    for (Container& c : containers_)
      for (const Box& k : kinematics)
        if (k.overlaps(c.outer)) c.live = false;
    const Energy before = energy();
    double fastest = 0;
    // The discrete mode promises containment only to bodies whose own travel in a step is less than their
    // radius (README, "Three ways to advance a world"): a step with a faster one is not held to it, and
    // whatever it carried out of a container is not either afterwards.
    bool discreteFast = false;
    const bool discrete = world_.definition().mode == rattle::StepMode::Discrete;
    for (BodyId b : bodies_) {
      if (!world_.isValid(b)) continue;
      const double speed = rattle::length(world_.velocity(b));
      fastest = std::max(fastest, speed);
      if (discrete && valid) {
        const std::optional<Disk> d = diskOf(world_, b);
        const double g = rattle::length(world_.definition().gravity);
        if (d && !(speed * dt + 0.5 * g * dt * dt < d->radius)) discreteFast = true;
      }
    }
    if (discreteFast)
      for (Container& c : containers_) c.live = false;
    const std::vector<Outside> outside = outsidePolygons();
    where.step = ++steps_;
    where.dt = dt;
    if (verbose()) {
      std::fprintf(stderr, "world_api: %s mode, gravity %s, step %d, dt %.17g, %d bodies:\n", modeName(where.mode),
                   where.gravity ? "on" : "off", steps_, dt, world_.bodyCount());
      for (BodyId b : bodies_) {
        if (!world_.isValid(b)) continue;
        const Vec2 p = world_.position(b), v = world_.velocity(b);
        std::fprintf(stderr, "  body (%u, %u) type %d at (%.17g, %.17g) velocity (%.17g, %.17g), %zu fixtures\n", b.index,
                     b.generation, static_cast<int>(world_.type(b)), p.x, p.y, v.x, v.y, world_.fixtures(b).size());
        for (FixtureId f : world_.fixtures(b)) {
          if (std::find(described_.begin(), described_.end(), f) != described_.end()) continue;
          described_.push_back(f);
          describe(f);
        }
      }
    }
    try {
      world_.step(dt);
    } catch (const rattle::Error& e) {
      if (valid && (checks & kStepError))
        finding("error", "step(%.17g) threw rattle::Error: %s", dt, e.what());
      return;
    }
    if (verbose()) {
      std::fprintf(stderr, "world_api: after step %d:\n", steps_);
      for (BodyId b : bodies_) {
        if (!world_.isValid(b)) continue;
        const Vec2 p = world_.position(b), v = world_.velocity(b);
        std::fprintf(stderr, "  body (%u, %u) at (%.17g, %.17g) velocity (%.17g, %.17g)\n", b.index, b.generation, p.x, p.y,
                     v.x, v.y);
      }
      // The step's contact events, the first and the last kShownContacts of them (a looping step has
      // 20,000, and the loop is at its end).
      constexpr size_t kShownContacts = 40;
      const auto contacts = world_.contactEvents();
      for (size_t k = 0; k < contacts.size(); ++k) {
        if (k == kShownContacts && contacts.size() > 2 * kShownContacts) {
          std::fprintf(stderr, "  ...\n");
          k = contacts.size() - kShownContacts;
        }
        const rattle::ContactEvent& e = contacts[k];
        std::fprintf(stderr,
                     "  contact at t %.17g: bodies %u and %u, point (%.17g, %.17g), normal (%.17g, %.17g), "
                     "impulse %.17g\n",
                     e.time, e.bodyA.index, e.bodyB.index, e.point.x, e.point.y, e.normal.x, e.normal.y, e.impulse);
      }
      std::fprintf(stderr, "  %zu contact events\n", contacts.size());
    }
    work_ += world_.stats().timeOfImpactTests + world_.stats().contactRowsSwept / kRowsPerTest;
    if (!valid && (checks & kStepError)) finding("error", "step(%.17g) was accepted; dt must be finite and >= 0", dt);
    if (valid) lastValidDt_ = dt;
    if (checks & kFinite) checkFinite();
    if ((checks & kBudget) && world_.stats().eventBudgetReached && fastest <= kBudgetSpeed) {
      constexpr const char* kReached = "the step reached WorldDef::maxEventsPerStep = %d (%d events processed, %d bodies)";
      if (reportedChecks() & kBudget) {
        report(kBudget, "budget", kReached, kEventBudget, world_.stats().eventsProcessed, world_.bodyCount());
      } else {
        finding("budget", kReached, kEventBudget, world_.stats().eventsProcessed, world_.bodyCount());
      }
    }
    if (checks & kEvents) checkEvents(dt);
    // The discrete mode's push-apart moves bodies against gravity without taking the energy from their
    // speed (README): its energy is checked without gravity only.
    const bool energyHolds = !(discrete && gravity()) &&
                             (!gravity() || ((checks & kGravityEnergy) && dt <= kLongestGravityStep));
    if ((checks & kEnergy) && kinematics.empty() && before.tracked && energyHolds) checkEnergy(before);
    if ((checks & kInside) && kinematics.empty() && !discreteFast) checkInside(outside);
    heldAtEnd_.clear();
    for (const Outside& o : outside) {
      if (!world_.isValid(o.disk) || !world_.isValid(o.polygon)) continue;
      const BodyId wall = world_.body(o.polygon);
      heldAtEnd_.push_back({o.disk, o.polygon, world_.position(o.disk), world_.position(wall)});
    }
    if (checks & kEscape) checkContainers();
    if (checks & kSave) checkSave();
    destroyedBodies_.clear();
    destroyedFixtures_.clear();
  }

  // One fixture, as a reproducer needs it (verbose only, the first step it is seen at).
  void describe(FixtureId f) const {
    const rattle::Filter fl = world_.filter(f);
    std::fprintf(stderr, "    fixture (%u, %u) %s density %.17g restitution %.17g%s filter %#x/%#x/%d:", f.index, f.generation,
                 rattle::nameOf(rattle::typeOf(world_.geometry(f))), world_.density(f), world_.restitution(f),
                 world_.isSensor(f) ? " sensor" : "", fl.categoryBits, fl.maskBits, fl.group);
    std::visit(
        [](const auto& g) {
          using T = std::decay_t<decltype(g)>;
          if constexpr (std::is_same_v<T, rattle::Point>) {
            std::fprintf(stderr, " (%.17g, %.17g)", g.position.x, g.position.y);
          } else if constexpr (std::is_same_v<T, rattle::Circle>) {
            std::fprintf(stderr, " centre (%.17g, %.17g) radius %.17g", g.center.x, g.center.y, g.radius);
          } else if constexpr (std::is_same_v<T, rattle::Segment>) {
            std::fprintf(stderr, " (%.17g, %.17g) (%.17g, %.17g)", g.a.x, g.a.y, g.b.x, g.b.y);
          } else {
            for (Vec2 q : g.points) std::fprintf(stderr, " (%.17g, %.17g)", q.x, q.y);
          }
        },
        world_.geometry(f));
    std::fprintf(stderr, "\n");
  }

  void checkFinite() const {
    for (BodyId b : bodies_) {
      if (!world_.isValid(b)) continue;
      const Vec2 p = world_.position(b), v = world_.velocity(b);
      if (!rattle::isFinite(p) || !rattle::isFinite(v))
        finding("finite", "body (%u, %u) of type %d: position (%.17g, %.17g), velocity (%.17g, %.17g)", b.index,
                b.generation, static_cast<int>(world_.type(b)), p.x, p.y, v.x, v.y);
    }
  }

  bool knownBody(BodyId b) const {
    return world_.isValid(b) || std::find(destroyedBodies_.begin(), destroyedBodies_.end(), b) != destroyedBodies_.end();
  }
  bool knownFixture(FixtureId f) const {
    return world_.isValid(f) ||
           std::find(destroyedFixtures_.begin(), destroyedFixtures_.end(), f) != destroyedFixtures_.end();
  }

  // A save loads, and the loaded world saves the same bytes and hashes the same.
  void checkSave() const {
    const std::vector<uint8_t> bytes = world_.save();
    try {
      const rattle::World loaded = rattle::World::load(bytes);
      if (loaded.save() != bytes || loaded.stateHash() != world_.stateHash())
        finding("save", "the loaded world's save (%zu bytes) or hash differs from the saved one's", bytes.size());
    } catch (const rattle::Error& e) {
      finding("save", "World::load refused a save of %zu bytes: %s", bytes.size(), e.what());
    }
  }

  // What a load builds anew (the broad phase, the predictive grid) may depend on the bytes alone: no
  // uninitialised memory, address or earlier history may reach a step of a loaded world.
  //
  // Their steps are at most kLongestGravityStep long: six steps of 1 s (two worlds, three steps each) of a
  // landing pile made most of the inputs that ran past libFuzzer's timeout, and what is checked here is
  // what a load builds, not long steps, which the program's own steps cover.
  void checkLoadsStepAlike() {
    const std::vector<uint8_t> bytes = world_.save();
    const double dt = std::min(lastValidDt_, kLongestGravityStep);
    where.step = steps_ + 1;
    where.dt = dt;
    try {
      rattle::World a = rattle::World::load(bytes);
      rattle::World b = rattle::World::load(bytes);
      for (int i = 0; i < kLoadedSteps; ++i) {
        a.step(dt);
        b.step(dt);
        if (a.save() != b.save())
          finding("save", "two worlds loaded from one save (%zu bytes) differ after %d step(s) of %.17g", bytes.size(),
                  i + 1, dt);
      }
    } catch (const rattle::Error& e) {
      finding("save", "a world loaded from a save (%zu bytes) threw rattle::Error: %s", bytes.size(), e.what());
    }
  }

  void checkEvents(double dt) const {
    // The budget bounds a step's changes of motion, whichever mode processed them (a predictive step
    // hands the rest of a pile's step to the hybrid step).
    if (world_.stats().eventsProcessed > kEventBudget)
      finding("events", "the step processed %d events, past WorldDef::maxEventsPerStep = %d",
              world_.stats().eventsProcessed, kEventBudget);
    const auto& contacts = world_.contactEvents();
    double last = 0;
    for (size_t i = 0; i < contacts.size(); ++i) {
      const rattle::ContactEvent& c = contacts[i];
      if (!knownFixture(c.fixtureA) || !knownFixture(c.fixtureB) || !knownBody(c.bodyA) || !knownBody(c.bodyB))
        finding("events", "contact event %zu names fixtures (%u, %u) and (%u, %u) of bodies (%u, %u) and (%u, %u): one is neither live nor destroyed since the last step",
                i, c.fixtureA.index, c.fixtureA.generation, c.fixtureB.index, c.fixtureB.generation, c.bodyA.index,
                c.bodyA.generation, c.bodyB.index, c.bodyB.generation);
      if (!(c.time >= 0 && c.time <= dt) || c.time < last)
        finding("events", "contact event %zu at time %.17g (previous %.17g; dt %.17g)", i, c.time, last, dt);
      last = c.time;
      const double n = rattle::length(c.normal);
      if (!(std::abs(n - 1) <= 1e-9) || !rattle::isFinite(c.point) || !(c.impulse >= 0) || !std::isfinite(c.impulse))
        finding("events", "contact event %zu of bodies (%u, %u) and (%u, %u): normal (%.17g, %.17g), point (%.17g, %.17g), impulse %.17g",
                i, c.bodyA.index, c.bodyA.generation, c.bodyB.index, c.bodyB.generation, c.normal.x, c.normal.y,
                c.point.x, c.point.y, c.impulse);
    }
    const auto& sensors = world_.sensorEvents();
    last = 0;
    for (size_t i = 0; i < sensors.size(); ++i) {
      const rattle::SensorEvent& s = sensors[i];
      if (!knownFixture(s.sensor) || !knownFixture(s.visitor) || !knownBody(s.sensorBody) || !knownBody(s.visitorBody))
        finding("events", "sensor event %zu (%s) names sensor (%u, %u) of body (%u, %u) and visitor (%u, %u) of body (%u, %u): one is neither live nor destroyed since the last step",
                i, s.begin ? "begin" : "end", s.sensor.index, s.sensor.generation, s.sensorBody.index,
                s.sensorBody.generation, s.visitor.index, s.visitor.generation, s.visitorBody.index,
                s.visitorBody.generation);
      if (!(s.time >= 0 && s.time <= dt) || s.time < last)
        finding("events", "sensor event %zu at time %.17g (previous %.17g; dt %.17g)", i, s.time, last, dt);
      last = s.time;
    }
  }

  void checkEnergy(const Energy& before) const {
    const Energy after = energy();
    double allowed = kEnergyTolerance * std::max(before.scale, after.scale);
    // Under gravity a contact slower than restingSpeed may leave at restingSpeed (WorldDef::restingSpeed):
    // that much energy per contact event is by design.
    if (gravity()) {
      const double s = world_.definition().restingSpeed;
      allowed += static_cast<double>(world_.contactEvents().size()) * 0.5 * std::max(before.maxMass, after.maxMass) * s * s;
    }
    if (after.total - before.total > allowed)
      finding("energy", "energy %.17g before the step, %.17g after (+%.3g, relative %.3g; allowed %.3g); %zu contact events",
              before.total, after.total, after.total - before.total,
              (after.total - before.total) / std::max(before.scale, 1e-300), allowed, world_.contactEvents().size());
  }

  void checkInside(const std::vector<Outside>& outside) const {
    for (const Outside& o : outside) {
      if (!world_.isValid(o.disk) || !world_.isValid(o.polygon)) continue;
      const std::optional<Disk> d = diskOf(world_, o.disk);
      if (!d || !inRange(*d)) continue;
      const BodyId wall = world_.body(o.polygon);
      const auto& polygon = std::get<rattle::Polygon>(world_.geometry(o.polygon));
      const double depth = depthInside(polygon, world_.position(wall), d->centre);
      if (depth > tolerance(d->radius)) {
        const Vec2 v = world_.velocity(o.disk);
        finding("inside", "dynamic body (%u, %u), radius %.17g, has its centre (%.17g, %.17g) %.17g inside static polygon fixture (%u, %u) (%.3g radii; tolerance 1%% + 1e-9); velocity (%.17g, %.17g)",
                o.disk.index, o.disk.generation, d->radius, d->centre.x, d->centre.y, depth, o.polygon.index,
                o.polygon.generation, depth / d->radius, v.x, v.y);
      }
    }
  }

  void checkContainers() {
    for (Container& c : containers_) {
      if (!c.live) continue;
      std::erase_if(c.members, [&](BodyId b) { return !world_.isValid(b); });
      for (BodyId b : c.members) {
        const std::optional<Disk> d = diskOf(world_, b);
        if (!d || !inRange(*d) || (d->radius == 0 && !c.holdsPoints)) continue;
        if (!inBox(c.inner, d->centre, tolerance(d->radius))) {
          const Vec2 v = world_.velocity(b);
          finding("escape", "dynamic body (%u, %u), radius %.17g, centre (%.17g, %.17g), velocity (%.17g, %.17g), is outside the closed container it was made in (body (%u, %u), inside [%.17g, %.17g] x [%.17g, %.17g])",
                  b.index, b.generation, d->radius, d->centre.x, d->centre.y, v.x, v.y, c.wall.index, c.wall.generation,
                  c.inner.min.x, c.inner.max.x, c.inner.min.y, c.inner.max.y);
        }
      }
    }
  }

  void query() {
    const uint8_t kind = in_.u8() % 6;
    rattle::QueryFilter qf;
    qf.includeSensors = (in_.u8() & 1) != 0;
    const bool check = (enabledChecks() & kQuery) != 0;
    std::vector<FixtureId> found;
    switch (kind) {
      case 0: {
        const Vec2 o = in_.vec(-100, 100);
        const auto hit = world_.rayCastFirst(o, in_.vec(-200, 200), qf);
        if (hit && check) checkRayHits({*hit});
        return;
      }
      case 1: {
        const Vec2 o = in_.vec(-100, 100);
        const auto hits = world_.rayCastAll(o, in_.vec(-200, 200), qf);
        if (check) checkRayHits(hits);
        return;
      }
      case 2: {
        const Vec2 a = in_.vec(-100, 100);
        found = world_.overlapBox({a, a + in_.vec(0, 50)}, qf);
        break;
      }
      case 3: {
        const Vec2 c = in_.vec(-100, 100);
        found = world_.overlapCircle(c, in_.real(0, 20), qf);
        break;
      }
      case 4:
        found = world_.overlapPoint(in_.vec(-100, 100), qf);
        break;
      default:
        found = world_.sensorOverlaps(anyFixture());
        break;
    }
    if (!check) return;
    for (size_t i = 0; i < found.size(); ++i) {
      if (!world_.isValid(found[i]))
        finding("query", "a query (kind %d) returned fixture (%u, %u), which is not live", kind, found[i].index,
                found[i].generation);
      if (i > 0 && !(found[i - 1].index < found[i].index))
        finding("query", "a query (kind %d) returned fixtures out of index order (%u then %u)", kind,
                found[i - 1].index, found[i].index);
    }
  }

  void checkRayHits(const std::vector<rattle::RayHit>& hits) const {
    for (size_t i = 0; i < hits.size(); ++i) {
      const rattle::RayHit& h = hits[i];
      if (!world_.isValid(h.fixture) || !world_.isValid(h.body) || !(h.fraction >= 0 && h.fraction <= 1))
        finding("query", "ray hit %zu: fixture (%u, %u), body (%u, %u), fraction %.17g", i, h.fixture.index,
                h.fixture.generation, h.body.index, h.body.generation, h.fraction);
      if (i > 0 && hits[i - 1].fraction > h.fraction)
        finding("query", "ray hits out of order: fraction %.17g then %.17g", hits[i - 1].fraction, h.fraction);
    }
  }

  // The getters and wake on any handle (stale ones throw).
  void look() {
    const BodyId b = anyBody();
    switch (in_.u8() % 4) {
      case 0:
        world_.wake(b);
        return;
      case 1:
        (void)world_.isAsleep(b);
        (void)world_.mass(b);
        (void)world_.userData(b);
        return;
      case 2:
        (void)world_.stateHash();
        return;
      default: {
        const FixtureId f = anyFixture();
        (void)world_.density(f);
        (void)world_.restitution(f);
        (void)world_.isSensor(f);
        (void)rattle::boxOf(world_.geometry(f));
        return;
      }
    }
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  Reader in(data, size);
  const uint8_t head = in.u8();
  rattle::WorldDef def;
  def.mode = static_cast<rattle::StepMode>(head % 3);
  if ((head / 3) % 2 == 1) def.gravity = {0, kGravity};
  def.maxEventsPerStep = kEventBudget;
  if (!modeEnabled(def.mode)) return 0;
  where = Where{def.mode, def.gravity.y != 0, 0, 0};
  input = Input{data, size, 0};
  rattle::World world(def);
  Program program(in, world);
  program.run();
  return 0;
}
