// A few disks bouncing in a closed box. Prints every contact event and, with --svg FILE, draws the
// paths of the disks as an SVG picture. It uses only the public headers (<rattle/rattle.h>).
#include <rattle/rattle.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

void usage(FILE* out) {
  std::fprintf(out,
               "usage: bounce_in_box [--svg FILE] [--steps N] [--quiet]\n"
               "  Disks with restitution 1 in a closed 20x12 box, stepped at 1/60 s.\n"
               "  --svg FILE   write the disks' paths as an SVG picture to FILE (default: none)\n"
               "  --steps N    number of steps (default 600)\n"
               "  --quiet      print only the summary, not every contact event\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::string svgPath;
  int steps = 600;
  bool quiet = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      usage(stdout);
      return 0;
    } else if ((!std::strcmp(argv[i], "--svg") || !std::strcmp(argv[i], "--steps")) && i + 1 == argc) {
      std::fprintf(stderr, "bounce_in_box: %s: a value is missing\n", argv[i]);
      return 2;
    } else if (!std::strcmp(argv[i], "--svg")) {
      svgPath = argv[++i];
      if (svgPath.empty()) {
        std::fprintf(stderr, "bounce_in_box: --svg: expected a file name\n");
        return 2;
      }
    } else if (!std::strcmp(argv[i], "--steps")) {
      char* end = nullptr;
      long n = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || n < 1 || n > 10'000'000) {
        std::fprintf(stderr, "bounce_in_box: --steps %s: expected a whole number from 1 to 10000000\n", argv[i]);
        return 2;
      }
      steps = static_cast<int>(n);
    } else if (!std::strcmp(argv[i], "--quiet")) {
      quiet = true;
    } else {
      std::fprintf(stderr, "bounce_in_box: unknown argument '%s'\n", argv[i]);
      usage(stderr);
      return 2;
    }
  }

  // Opened before the run, so that a path that cannot be written fails at once.
  FILE* svg = nullptr;
  if (!svgPath.empty() && !(svg = std::fopen(svgPath.c_str(), "w"))) {
    std::fprintf(stderr, "bounce_in_box: cannot write %s: %s\n", svgPath.c_str(), std::strerror(errno));
    return 1;
  }

  const double width = 20, height = 12, dt = 1.0 / 60.0;
  rattle::World world;
  rattle::BodyId box = world.createBody({});
  const rattle::Vec2 corners[4] = {{0, 0}, {width, 0}, {width, height}, {0, height}};
  for (int i = 0; i < 4; ++i) {
    world.createFixture(box, {.geometry = rattle::Segment{corners[i], corners[(i + 1) % 4]}, .restitution = 1});
  }
  struct Disk {
    rattle::BodyId id;
    double radius;
    const char* colour;
    std::vector<rattle::Vec2> path;
  };
  std::vector<Disk> disks = {
      {{}, 1.0, "#d9534f", {}}, {{}, 0.6, "#5bc0de", {}}, {{}, 0.8, "#5cb85c", {}}, {{}, 0.4, "#f0ad4e", {}}};
  const rattle::Vec2 starts[4] = {{4, 6}, {10, 3}, {15, 8}, {8, 9}};
  const rattle::Vec2 velocities[4] = {{7, 3}, {-5, 6}, {-4, -6}, {12, -2}};
  for (size_t i = 0; i < disks.size(); ++i) {
    disks[i].id =
        world.createBody({.type = rattle::BodyType::Dynamic, .position = starts[i], .velocity = velocities[i]});
    world.createFixture(disks[i].id, {.geometry = rattle::Circle{{0, 0}, disks[i].radius}, .restitution = 1});
    disks[i].path.push_back(starts[i]);
  }

  long contacts = 0;
  for (int s = 0; s < steps; ++s) {
    const double stepStart = world.time();
    world.step(dt);
    for (const rattle::ContactEvent& c : world.contactEvents()) {
      ++contacts;
      if (!quiet) {
        std::printf("t=%9.5f  fixtures %u-%u  point (%7.3f, %7.3f)  normal (%6.3f, %6.3f)  impulse %.4f\n",
                    stepStart + c.time, c.fixtureA.index, c.fixtureB.index, c.point.x, c.point.y, c.normal.x,
                    c.normal.y, c.impulse);
      }
    }
    for (Disk& d : disks) d.path.push_back(world.position(d.id));
  }
  std::printf("%d steps, %.2f s simulated, %ld contact events\n", steps, world.time(), contacts);

  if (svg) {
    FILE* f = svg;
    const double scale = 40;
    std::fprintf(f, "<svg xmlns='http://www.w3.org/2000/svg' width='%g' height='%g'>\n", width * scale, height * scale);
    std::fprintf(f, "<rect width='100%%' height='100%%' fill='#fdfdfd' stroke='#333' stroke-width='4'/>\n");
    for (const Disk& d : disks) {
      std::fprintf(f, "<polyline fill='none' stroke='%s' stroke-opacity='0.5' stroke-width='1.5' points='", d.colour);
      for (rattle::Vec2 p : d.path) std::fprintf(f, "%.2f,%.2f ", p.x * scale, (height - p.y) * scale);
      std::fprintf(f, "'/>\n");
      rattle::Vec2 p = d.path.back();
      std::fprintf(f, "<circle cx='%.2f' cy='%.2f' r='%.2f' fill='%s'/>\n", p.x * scale, (height - p.y) * scale,
                   d.radius * scale, d.colour);
    }
    std::fprintf(f, "</svg>\n");
    if (std::fclose(f) != 0) {
      std::fprintf(stderr, "bounce_in_box: cannot write %s: %s\n", svgPath.c_str(), std::strerror(errno));
      return 1;
    }
    std::printf("wrote %s\n", svgPath.c_str());
  }
  return 0;
}
