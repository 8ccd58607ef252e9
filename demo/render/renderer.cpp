// The drawing: every shape is turned into triangles on the CPU (in screen pixels) and drawn with one
// vertex array per layer. Plain OpenGL 1.1, which every Mesa driver and every window system has.
#include "render/renderer.h"

#include <GL/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "render/hud_text.h"

namespace rts {
namespace {

constexpr double kPi = 3.141592653589793;

struct Colour {
  float r, g, b, a;
  Colour withAlpha(float alpha) const { return {r, g, b, alpha}; }
  Colour scaled(float k) const { return {r * k, g * k, b * k, a}; }
};

const Colour kBackground{0.25f, 0.29f, 0.22f, 1};
const Colour kRoomFloor{0.33f, 0.33f, 0.30f, 1};
const Colour kTeam[2] = {{0.30f, 0.58f, 1.00f, 1}, {1.00f, 0.36f, 0.28f, 1}};
const Colour kContested{0.80f, 0.45f, 0.95f, 1};
const Colour kWallLine{0.80f, 0.76f, 0.66f, 1};
const Colour kWallFill{0.50f, 0.48f, 0.44f, 1};
const Colour kBuildingFill{0.40f, 0.33f, 0.27f, 1};
const Colour kBuildingEdge{0.62f, 0.52f, 0.42f, 1};
const Colour kGateFill{0.85f, 0.62f, 0.20f, 1};
const Colour kGateEdge{1.0f, 0.85f, 0.45f, 1};
const Colour kDoorway{1.0f, 0.88f, 0.35f, 0.9f};
const Colour kShot{1.0f, 1.0f, 0.9f, 1};

struct Vertex {
  float x, y;
  uint8_t r, g, b, a;
};

uint8_t byte(float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

// Triangles in screen pixels, drawn in one call.
class Batch {
 public:
  explicit Batch(const View& view) : view_(view) {}

  void vertex(Vec2 screen, Colour c) {
    v_.push_back({float(screen.x), float(screen.y), byte(c.r), byte(c.g), byte(c.b), byte(c.a)});
  }
  void triangleScreen(Vec2 a, Vec2 b, Vec2 c, Colour ca, Colour cb, Colour cc) {
    vertex(a, ca);
    vertex(b, cb);
    vertex(c, cc);
  }
  // World-space shapes.
  void polygon(const std::vector<Vec2>& pts, Colour c) {
    for (size_t i = 1; i + 1 < pts.size(); ++i) {
      triangleScreen(view_.toScreen(pts[0]), view_.toScreen(pts[i]), view_.toScreen(pts[i + 1]), c, c, c);
    }
  }
  void disk(Vec2 center, double radius, Colour c) { ring(center, 0, radius, c, c); }
  // The annulus between two radii (inner may be 0), colours at the inner and outer edge.
  void ring(Vec2 center, double inner, double outer, Colour cin, Colour cout) {
    const Vec2 s = view_.toScreen(center);
    const double ro = outer * view_.scale, ri = inner * view_.scale;
    const int n = std::clamp(int(std::ceil(2 * kPi * ro / 3.0)), 10, 128);
    for (int i = 0; i < n; ++i) {
      const double a0 = 2 * kPi * i / n, a1 = 2 * kPi * (i + 1) / n;
      const Vec2 d0{std::cos(a0), std::sin(a0)}, d1{std::cos(a1), std::sin(a1)};
      if (ri <= 0) {
        triangleScreen(s, s + d0 * ro, s + d1 * ro, cin, cout, cout);
      } else {
        triangleScreen(s + d0 * ri, s + d0 * ro, s + d1 * ro, cin, cout, cout);
        triangleScreen(s + d0 * ri, s + d1 * ro, s + d1 * ri, cin, cout, cin);
      }
    }
  }
  // A thick segment; colours may differ at the two ends (trails).
  void line(Vec2 a, Vec2 b, double width, Colour ca, Colour cb) {
    const Vec2 sa = view_.toScreen(a), sb = view_.toScreen(b);
    Vec2 d = sb - sa;
    const double l = rattle::length(d);
    if (l <= 1e-9) return;
    const Vec2 n = rattle::perpendicular(d * (1.0 / l)) * (width * view_.scale * 0.5);
    triangleScreen(sa + n, sa - n, sb - n, ca, ca, cb);
    triangleScreen(sa + n, sb - n, sb + n, ca, cb, cb);
  }
  void outline(const std::vector<Vec2>& pts, bool closed, double width, Colour c) {
    for (size_t i = 0; i + 1 < pts.size(); ++i) line(pts[i], pts[i + 1], width, c, c);
    if (closed && pts.size() > 2) line(pts.back(), pts.front(), width, c, c);
    for (Vec2 p : pts) disk(p, width * 0.5, c);  // round joins
  }
  void rectScreen(Vec2 a, Vec2 b, Colour c) {
    triangleScreen(a, {b.x, a.y}, b, c, c, c);
    triangleScreen(a, b, {a.x, b.y}, c, c, c);
  }

  void draw() {
    if (v_.empty()) return;
    glVertexPointer(2, GL_FLOAT, sizeof(Vertex), &v_[0].x);
    glColorPointer(4, GL_UNSIGNED_BYTE, sizeof(Vertex), &v_[0].r);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(v_.size()));
    v_.clear();
  }

 private:
  const View& view_;
  std::vector<Vertex> v_;
};

Colour holderColour(int holder) { return holder == 2 ? kContested : kTeam[holder & 1]; }

}  // namespace

View fitView(double worldWidth, double worldHeight, int width, int height) {
  View v;
  v.scale = std::min(double(width) / worldWidth, double(height) / worldHeight);
  v.offset = {(double(width) - worldWidth * v.scale) * 0.5, (double(height) - worldHeight * v.scale) * 0.5};
  return v;
}

void drawScene(const Scene& scene, int width, int height) {
  const View view = fitView(scene.worldWidth, scene.worldHeight, width, height);
  glViewport(0, 0, width, height);
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glOrtho(0, width, height, 0, -1, 1);
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  glClearColor(0.05f, 0.05f, 0.06f, 1);
  glClearStencil(0);
  glClear(GL_COLOR_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);

  Batch b(view);
  // Ground, rooms tinted by who holds them.
  b.rectScreen(view.toScreen({0, 0}), view.toScreen({scene.worldWidth, scene.worldHeight}), kBackground);
  for (const SceneRoom& r : scene.rooms) {
    b.polygon(r.polygon, kRoomFloor);
    if (r.holder >= 0) b.polygon(r.polygon, holderColour(r.holder).withAlpha(0.16f));
  }
  b.draw();
  // Sight ranges: the outline of each team's union of disks, a thin line, drawn once. Filled disks,
  // even a union tinted once, lay a veil over every fight, where the ranges overlap most.
  const double onePixel = double(height) / 720.0;  // a pixel of a 720-line frame, in framebuffer pixels
  const double sightLine = 1.5 * onePixel / view.scale;
  for (int team = 0; team < 2; ++team) {
    bool any = false;
    for (const SceneSight& s : scene.sight) any |= s.team == team;
    if (!any) continue;
    // Mark the inside of every disk less the line's width; then draw the whole disks where nothing is
    // marked, marking what is drawn: what is left is the union's boundary, each pixel blended once.
    glEnable(GL_STENCIL_TEST);
    glClear(GL_STENCIL_BUFFER_BIT);
    glStencilFunc(GL_ALWAYS, 1, 1);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    for (const SceneSight& s : scene.sight) {
      if (s.team == team && s.radius > sightLine) b.disk(s.center, s.radius - sightLine, {0, 0, 0, 0});
    }
    b.draw();
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glStencilFunc(GL_EQUAL, 0, 1);
    glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
    for (const SceneSight& s : scene.sight) {
      if (s.team == team) b.disk(s.center, s.radius, kTeam[team].withAlpha(0.45f));
    }
    b.draw();
    glDisable(GL_STENCIL_TEST);
  }
  // Doorways: a dashed line, lit in the colour of the last team through it.
  for (const SceneDoorway& d : scene.doorways) {
    const double l = rattle::length(d.b - d.a);
    const int dashes = std::max(1, int(l / 0.8));
    for (int i = 0; i < dashes; i += 2) {
      b.line(d.a + (d.b - d.a) * (double(i) / dashes), d.a + (d.b - d.a) * (double(i + 1) / dashes), 0.35, kDoorway, kDoorway);
    }
    if (d.glow > 0) {
      const Colour c = kTeam[d.team & 1].withAlpha(float(0.85 * d.glow));
      b.line(d.a, d.b, 0.35 + 1.2 * d.glow, c, c);
    }
  }
  // Walls, buildings, gates.
  for (const SceneWall& w : scene.walls) {
    switch (w.shape) {
      case SceneWall::Shape::Lines:
        b.outline(w.points, false, 0.5, kWallLine);
        break;
      case SceneWall::Shape::Polygon:
        b.polygon(w.points, w.building ? kBuildingFill : kWallFill);
        b.outline(w.points, true, 0.3, w.building ? kBuildingEdge : kWallLine);
        break;
      case SceneWall::Shape::Circle:
        b.disk(w.center, w.radius, w.building ? kBuildingFill : kWallFill);
        b.ring(w.center, w.radius - 0.3, w.radius, w.building ? kBuildingEdge : kWallLine, w.building ? kBuildingEdge : kWallLine);
        break;
    }
  }
  for (const std::vector<Vec2>& g : scene.gates) {
    b.polygon(g, kGateFill);
    b.outline(g, true, 0.2, kGateEdge);
  }
  // Projectiles: a bright head in a halo of the team's colour, and a tapering trail of the last two
  // ticks of flight. Drawn at the game's size (a trooper's is 0.3 units across, 2 pixels at 1280x720
  // on the arena) a shot is lost in a fight; a player reads them as tracers, so they are drawn several
  // times larger. Under the fog like the ground they fly over.
  for (const SceneShot& s : scene.shots) {
    const Colour team = kTeam[s.team & 1];
    const Colour hot{std::min(1.0f, team.r + 0.4f), std::min(1.0f, team.g + 0.4f), std::min(1.0f, team.b + 0.4f), 1};
    b.line(s.position - s.velocity * 0.07, s.position, s.radius * 3.5, team.withAlpha(0), hot.withAlpha(0.95f));
    b.ring(s.position, 0, s.radius * 6.0, team.withAlpha(0.9f), team.withAlpha(0));
    b.line(s.position - s.velocity * 0.035, s.position, s.radius * 1.4, kShot.withAlpha(0), kShot);
    b.disk(s.position, s.radius * 2.5, kShot);
  }
  for (const SceneImpact& i : scene.impacts) {
    const float a = float(1 - i.age);
    const Colour c = i.wall ? Colour{1.0f, 0.6f, 0.2f, a} : Colour{1, 1, 1, a};
    b.ring(i.position, 0.2 + 0.9 * i.age, 0.45 + 1.0 * i.age, c.withAlpha(0), c);
  }
  b.draw();

  // Fog of war: mark what the team sees in the stencil buffer, then dim everything else.
  if (scene.fog) {
    glEnable(GL_STENCIL_TEST);
    glClear(GL_STENCIL_BUFFER_BIT);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glStencilFunc(GL_ALWAYS, 1, 1);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    const Colour none{0, 0, 0, 0};
    for (const std::vector<Vec2>& fan : scene.fogFans) {
      for (size_t i = 1; i < fan.size(); ++i) {
        const size_t j = i + 1 < fan.size() ? i + 1 : 1;
        b.triangleScreen(view.toScreen(fan[0]), view.toScreen(fan[i]), view.toScreen(fan[j]), none, none, none);
      }
    }
    b.draw();
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glStencilFunc(GL_EQUAL, 0, 1);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    b.rectScreen({0, 0}, {double(width), double(height)}, {0.0f, 0.0f, 0.04f, 0.55f});
    b.draw();
    glDisable(GL_STENCIL_TEST);
  }

  // Units on top, undimmed: the scene holds only the units the fog team sees (scene_builder.cpp), and a
  // unit seen by the rule (sensor and a clear line) may stand just outside the fog's ray-cast outline.
  for (const SceneUnit& u : scene.units) {
    const Colour c = kTeam[u.team & 1];
    if (u.selected) b.ring(u.position, u.radius + 0.15, u.radius + 0.45, {1, 1, 1, 0.9f}, {1, 1, 1, 0.9f});
    b.disk(u.position, u.radius, c.scaled(0.45f));
    b.disk(u.position, u.radius * 0.72, c);
    if (u.health < 1) b.disk(u.position, u.radius * 0.3, Colour{0.1f, 0.1f, 0.1f, float(1 - u.health)});
  }
  if (scene.hasSelectionBox) {
    const Vec2 a = view.toScreen(scene.selectionA), c = view.toScreen(scene.selectionB);
    const Vec2 lo{std::min(a.x, c.x), std::min(a.y, c.y)}, hi{std::max(a.x, c.x), std::max(a.y, c.y)};
    b.rectScreen(lo, hi, {1, 1, 1, 0.12f});
    const double t = std::max(1.0, double(height) / 720.0);
    b.rectScreen(lo, {hi.x, lo.y + t}, {1, 1, 1, 0.8f});
    b.rectScreen({lo.x, hi.y - t}, hi, {1, 1, 1, 0.8f});
    b.rectScreen(lo, {lo.x + t, hi.y}, {1, 1, 1, 0.8f});
    b.rectScreen({hi.x - t, lo.y}, hi, {1, 1, 1, 0.8f});
  }

  // HUD: text on a dark band; sized from the frame height so every resolution looks alike.
  const float scale = float(std::max(1.0, std::round(double(height) / 360.0)));
  const float lineHeight = 10 * scale;
  float widest = 0;
  for (const std::string& l : scene.hud) widest = std::max(widest, textWidth(l, scale));
  if (!scene.hud.empty()) {
    b.rectScreen({0, 0}, {double(widest + 12 * scale), double(lineHeight * float(scene.hud.size()) + 6 * scale)},
                 {0, 0, 0, 0.6f});
  }
  for (size_t i = 0; i < scene.hud.size(); ++i) {
    for (const TextQuad& q : textQuads(scene.hud[i], 6 * scale, 4 * scale + lineHeight * float(i), scale)) {
      b.rectScreen({q.x0, q.y0}, {q.x1, q.y1}, {0.95f, 0.95f, 0.9f, 1});
    }
  }
  b.draw();
  glFinish();
}

}  // namespace rts
