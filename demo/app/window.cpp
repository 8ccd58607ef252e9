// The SDL2 window. The picture is the offscreen renderer's (the same pixels a PNG frame would have),
// shown through an SDL texture, so the window needs no OpenGL of its own and looks exactly like the
// headless frames. The person plays blue (team 0) against the scripted opponent's red; with --host or
// --join this side's team against the peer's, with --watch nobody (demo/README.md, "Network play").
//
//   left-drag   select your units (a click selects the nearest one)
//   right-click move the selection there
//   space       pause / resume (not in a network game: the peer would wait without knowing why)
//   v           sight ranges on / off
//   g           open / close the first gate
//   f           fog of war: blue's view, red's view, none (not a network player: it sees its own team's)
//   Esc, q      quit (in a network game: leave it, telling the peer)
//
// --input FILE plays scripted events through the same handlers (for the Xvfb test); each line is
// "FRAME EVENT ARGS": `drag X0 Y0 X1 Y1`, `click X Y`, `rclick X Y`, `key NAME` (space, v, g, f, q,
// escape) or `quit`, with window pixel coordinates. With a script the game runs one tick per frame, so
// a script means the same thing on a fast machine and a slow one.
#include <SDL.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/network_play.h"
#include "app/run.h"
#include "game/opponent.h"
#include "game/tick_loop.h"
#include "map/errno_reason.h"
#include "render/offscreen.h"
#include "render/png.h"
#include "render/renderer.h"
#include "render/scene_builder.h"
#include "tool/recorder.h"

namespace rts {
namespace {

// The person's orders, given between ticks and played at the next one.
class PlayerOrders : public CommandSource {
 public:
  void push(Command c) { queued_.push_back(std::move(c)); }
  void commandsFor(uint32_t tick, const Game&, std::vector<Command>& out) override {
    for (Command& c : queued_) {
      c.tick = tick;
      out.push_back(std::move(c));
    }
    queued_.clear();
  }

 private:
  std::vector<Command> queued_;
};

struct ScriptedEvent {
  long frame = 0;
  SDL_Event events[3];
  int count = 0;
};

SDL_Keycode keyNamed(const std::string& name) {
  if (name == "space") return SDLK_SPACE;
  if (name == "escape") return SDLK_ESCAPE;
  if (name.size() == 1 && name[0] >= 'a' && name[0] <= 'z') return SDL_Keycode(name[0]);
  return SDLK_UNKNOWN;
}

// Reads an input script; returns an error naming the line, or "".
std::string readScript(const std::string& path, Uint32 windowId, std::vector<ScriptedEvent>& out) {
  // A directory opens and reads as empty: it would pass for a script with no events.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return path + ": is a directory, not an input script";
  errno = 0;
  std::ifstream in(path);
  if (!in) return path + ": cannot open the input script" + errnoReason();
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.size() > 1000) return path + ":" + std::to_string(number) + ": line too long";
    std::istringstream ss(line);
    std::string word;
    ScriptedEvent e;
    if (!(ss >> word) || word[0] == '#') continue;
    try {
      e.frame = std::stol(word);
    } catch (const std::exception&) {
      return path + ":" + std::to_string(number) + ": '" + word + "': expected a frame number";
    }
    std::string kind;
    ss >> kind;
    auto button = [&](Uint32 type, Uint8 which, int x, int y) {
      SDL_Event ev{};
      ev.type = type;
      ev.button.windowID = windowId;
      ev.button.button = which;
      ev.button.state = type == SDL_MOUSEBUTTONDOWN ? SDL_PRESSED : SDL_RELEASED;
      ev.button.clicks = 1;
      ev.button.x = x;
      ev.button.y = y;
      e.events[e.count++] = ev;
    };
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    if (kind == "drag" && (ss >> x0 >> y0 >> x1 >> y1)) {
      button(SDL_MOUSEBUTTONDOWN, SDL_BUTTON_LEFT, x0, y0);
      SDL_Event motion{};
      motion.type = SDL_MOUSEMOTION;
      motion.motion.windowID = windowId;
      motion.motion.x = x1;
      motion.motion.y = y1;
      e.events[e.count++] = motion;
      button(SDL_MOUSEBUTTONUP, SDL_BUTTON_LEFT, x1, y1);
    } else if ((kind == "click" || kind == "rclick") && (ss >> x0 >> y0)) {
      const Uint8 which = kind == "click" ? SDL_BUTTON_LEFT : SDL_BUTTON_RIGHT;
      button(SDL_MOUSEBUTTONDOWN, which, x0, y0);
      button(SDL_MOUSEBUTTONUP, which, x0, y0);
    } else if (kind == "key" && (ss >> word) && keyNamed(word) != SDLK_UNKNOWN) {
      SDL_Event ev{};
      ev.type = SDL_KEYDOWN;
      ev.key.windowID = windowId;
      ev.key.state = SDL_PRESSED;
      ev.key.keysym.sym = keyNamed(word);
      e.events[e.count++] = ev;
    } else if (kind == "quit") {
      SDL_Event ev{};
      ev.type = SDL_QUIT;
      e.events[e.count++] = ev;
    } else {
      return path + ":" + std::to_string(number) + ": '" + line +
             "': expected drag X0 Y0 X1 Y1, click X Y, rclick X Y, key NAME or quit";
    }
    out.push_back(e);
  }
  std::stable_sort(out.begin(), out.end(), [](const ScriptedEvent& a, const ScriptedEvent& b) { return a.frame < b.frame; });
  return "";
}

struct Sdl {
  SDL_Window* window = nullptr;
  SDL_Renderer* renderer = nullptr;
  SDL_Texture* texture = nullptr;
  ~Sdl() {
    if (texture) SDL_DestroyTexture(texture);
    if (renderer) SDL_DestroyRenderer(renderer);
    if (window) SDL_DestroyWindow(window);
    SDL_Quit();
  }
};

}  // namespace

int runWindow(Game& game, const Options& o, const std::string& mapJson, replay::Recorder* recorder) {
  // Software SDL rendering: the picture is already made; this only copies it to the window. No OpenGL
  // on SDL's side at all (not even to speed up the window surface): a second Mesa driver loaded next to
  // OSMesa would share its dispatch table and crash.
  SDL_SetHint(SDL_HINT_RENDER_DRIVER, "software");
  SDL_SetHint(SDL_HINT_FRAMEBUFFER_ACCELERATION, "0");
  // Without a display SDL falls back to a driver that draws nowhere (offscreen), and the game would run
  // unseen and exit 0. SDL_VIDEODRIVER set by hand (kmsdrm on a console, say) is taken as meant.
  const char* chosenDriver = std::getenv("SDL_VIDEODRIVER");
  const bool driverChosen = chosenDriver && *chosenDriver;
  auto isSet = [](const char* name) {
    const char* v = std::getenv(name);
    return v && *v;
  };
  if (!driverChosen && !isSet("DISPLAY") && !isSet("WAYLAND_DISPLAY")) {
    std::fprintf(stderr,
                 "rattle-demo: cannot open a window: no display (DISPLAY and WAYLAND_DISPLAY are both unset); "
                 "run it on a desktop, under xvfb-run, or without --window for PNG frames\n");
    return 1;
  }
  if (SDL_Init(SDL_INIT_VIDEO) != 0) {
    std::fprintf(stderr, "rattle-demo: cannot open a window: SDL's video init failed: %s (DISPLAY=%s, WAYLAND_DISPLAY=%s)\n",
                 SDL_GetError(), isSet("DISPLAY") ? std::getenv("DISPLAY") : "(unset)",
                 isSet("WAYLAND_DISPLAY") ? std::getenv("WAYLAND_DISPLAY") : "(unset)");
    return 1;
  }
  if (const char* driver = SDL_GetCurrentVideoDriver();
      !driverChosen && driver && (std::strcmp(driver, "offscreen") == 0 || std::strcmp(driver, "dummy") == 0)) {
    std::fprintf(stderr, "rattle-demo: cannot open a window: SDL found no display it can use (its video driver is '%s'; DISPLAY=%s, WAYLAND_DISPLAY=%s)\n",
                 driver, isSet("DISPLAY") ? std::getenv("DISPLAY") : "(unset)", isSet("WAYLAND_DISPLAY") ? std::getenv("WAYLAND_DISPLAY") : "(unset)");
    SDL_Quit();
    return 1;
  }
  Sdl sdl;
  sdl.window = SDL_CreateWindow("rattle demo", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, o.width, o.height, 0);
  if (sdl.window) sdl.renderer = SDL_CreateRenderer(sdl.window, -1, SDL_RENDERER_SOFTWARE);
  if (sdl.renderer) {
    sdl.texture = SDL_CreateTexture(sdl.renderer, SDL_PIXELFORMAT_RGBA32, SDL_TEXTUREACCESS_STREAMING, o.width, o.height);
  }
  if (!sdl.texture) {
    std::fprintf(stderr, "rattle-demo: cannot open a window: %s\n", SDL_GetError());
    return 1;
  }
  std::vector<ScriptedEvent> script;
  if (!o.inputScript.empty()) {
    std::string error = readScript(o.inputScript, SDL_GetWindowID(sdl.window), script);
    if (!error.empty()) {
      std::fprintf(stderr, "rattle-demo: %s\n", error.c_str());
      return 1;
    }
  }

  using Clock = std::chrono::steady_clock;
  const bool networked = o.network != Options::Network::None;
  const bool watching = o.network == Options::Network::Watch;
  const int team = o.team();  // the person's; a spectator gives no orders
  OffscreenRenderer offscreen(o.width, o.height, o.supersample);
  ScriptedOpponent opponent(o.seed, 2);  // red, in a game without a network only
  const View view = fitView(game.map().width, game.map().height, o.width, o.height);
  SceneOptions sceneOptions;
  sceneOptions.fogTeam = o.fogTeam;
  sceneOptions.showSight = o.showSight;
  sceneOptions.showTimes = o.showTimes;
  PlayerOrders mine;
  TickLoop loop(game);
  bool paused = false, quit = false, dragging = false;
  Vec2 dragFrom, dragTo;  // window pixels
  size_t nextScripted = 0;
  long frame = 0;
  double owed = 0;  // seconds of game time not yet run
  auto last = Clock::now();
  auto lastShown = last;
  // The HUD's network line while nothing is awaited. Space does nothing in a network game: a pause here
  // would only stall the peer, which could not tell it from a lost connection.
  const std::string networkLine =
      watching ? "watching the host's game: no orders; space does not pause it"
               : std::string("network game: you play ") + teamName(team) + " against " + teamName(1 - team) +
                     "; space does not pause it, f keeps your fog";

  auto select = [&](Vec2 a, Vec2 b) {
    sceneOptions.selected.assign(game.units().size(), 0);
    if (watching) return;
    const Vec2 wa = view.toWorld(a), wb = view.toWorld(b);
    const Vec2 lo{std::min(wa.x, wb.x), std::min(wa.y, wb.y)}, hi{std::max(wa.x, wb.x), std::max(wa.y, wb.y)};
    const bool click = rattle::length(b - a) < 4;
    double best = 1.5;
    int nearest = -1;
    for (const Unit& u : game.units()) {
      if (!u.alive || u.team != team) continue;
      if (click) {
        const double d = rattle::length(u.position - wa);
        if (d < best) best = d, nearest = int(u.id);
      } else if (u.position.x >= lo.x && u.position.x <= hi.x && u.position.y >= lo.y && u.position.y <= hi.y) {
        sceneOptions.selected[u.id] = 1;
      }
    }
    if (nearest >= 0) sceneOptions.selected[size_t(nearest)] = 1;
  };

  // One event, in the main loop or while a network game waits for the peer: orders go onto `mine`, which
  // gives them at the next tick it is asked for.
  auto handle = [&](const SDL_Event& ev) {
    if (ev.type == SDL_QUIT) {
      quit = true;
    } else if (ev.type == SDL_MOUSEBUTTONDOWN && ev.button.button == SDL_BUTTON_LEFT) {
      dragging = true;
      dragFrom = dragTo = {double(ev.button.x), double(ev.button.y)};
    } else if (ev.type == SDL_MOUSEMOTION && dragging) {
      dragTo = {double(ev.motion.x), double(ev.motion.y)};
    } else if (ev.type == SDL_MOUSEBUTTONUP && ev.button.button == SDL_BUTTON_LEFT && dragging) {
      dragging = false;
      dragTo = {double(ev.button.x), double(ev.button.y)};
      select(dragFrom, dragTo);
    } else if (ev.type == SDL_MOUSEBUTTONDOWN && ev.button.button == SDL_BUTTON_RIGHT && !watching) {
      Command c;
      c.team = uint8_t(team);
      c.type = CommandType::Move;
      c.target = view.toWorld({double(ev.button.x), double(ev.button.y)});
      for (size_t id = 0; id < sceneOptions.selected.size(); ++id) {
        if (sceneOptions.selected[id] && game.units()[id].alive) c.units.push_back(uint32_t(id));
      }
      if (!c.units.empty()) mine.push(std::move(c));
    } else if (ev.type == SDL_KEYDOWN) {
      switch (ev.key.keysym.sym) {
        case SDLK_SPACE:
          if (!networked) paused = !paused;
          break;
        case SDLK_v: sceneOptions.showSight = !sceneOptions.showSight; break;
        case SDLK_f:
          // A network player keeps its own team's fog: another would show it the peer's side.
          if (!networked || watching) {
            sceneOptions.fogTeam = sceneOptions.fogTeam == 0 ? 1 : sceneOptions.fogTeam == 1 ? -1 : 0;
          }
          break;
        case SDLK_g:
          if (!game.map().gates.empty() && !watching) {
            Command c;
            c.team = uint8_t(team);
            c.type = CommandType::ToggleGate;
            mine.push(std::move(c));
          }
          break;
        case SDLK_ESCAPE:
        case SDLK_q: quit = true; break;
        default: break;
      }
    }
  };
  auto handleEvents = [&]() {
    SDL_Event ev;
    while (SDL_PollEvent(&ev)) handle(ev);
  };

  // Draws the game as it is now; `final`: the window's last picture, which --screenshot saves.
  auto show = [&](bool final) -> bool {
    sceneOptions.paused = paused;
    sceneOptions.hasSelectionBox = dragging;
    sceneOptions.selectionA = view.toWorld(dragFrom);
    sceneOptions.selectionB = view.toWorld(dragTo);
    const std::vector<uint8_t>& pixels = offscreen.render(buildScene(game, sceneOptions));
    SDL_UpdateTexture(sdl.texture, nullptr, pixels.data(), o.width * 4);
    SDL_RenderClear(sdl.renderer);
    SDL_RenderCopy(sdl.renderer, sdl.texture, nullptr, nullptr);
    if (final && !o.screenshot.empty()) {
      // Read back what the window was given, not the offscreen buffer: this is the window's picture.
      std::vector<uint8_t> shot(size_t(o.width) * size_t(o.height) * 4);
      if (SDL_RenderReadPixels(sdl.renderer, nullptr, SDL_PIXELFORMAT_RGBA32, shot.data(), o.width * 4) != 0) {
        std::fprintf(stderr, "rattle-demo: cannot read the window back: %s\n", SDL_GetError());
        return false;
      }
      std::string error = writePng(o.screenshot, o.width, o.height, shot);
      if (!error.empty()) {
        std::fprintf(stderr, "rattle-demo: %s\n", error.c_str());
        return false;
      }
    }
    SDL_RenderPresent(sdl.renderer);
    lastShown = Clock::now();
    return true;
  };

  // While the session waits for the peer (or for it to connect): the window keeps handling events, and
  // once the wait outlasts an ordinary round trip it shows whom it waits for and for how long, at some
  // 30 frames a second. A quit leaves the game (the session tells the peer).
  auto whileWaiting = [&](const std::string& what, double seconds) -> bool {
    handleEvents();
    if (quit) return false;
    if (seconds >= 0.2 && Clock::now() - lastShown >= std::chrono::milliseconds(33)) {
      char text[40];
      std::snprintf(text, sizeof text, " (%.1f s)", seconds);
      sceneOptions.banner = "waiting for " + what + text;
      show(false);  // a screenshot is only ever of the last frame
    }
    return true;
  };

  Network network;
  std::string leftWhile;  // set when the person left a network game: why, or what it waited for then
  // The person quit while the session waited: the frame shown last was one of the wait's, so the
  // window's last picture is drawn again for --screenshot.
  auto leftWaiting = [&](const net::LeftGame& e) {
    leftWhile = std::string("you quit while ") + e.what();
    return o.screenshot.empty() || show(true);
  };
  if (networked) {
    try {
      network = connectNetwork(game, o, mapJson, mine, whileWaiting);
    } catch (const net::LeftGame& e) {
      if (!leftWaiting(e)) return 1;
    } catch (const net::SessionError& e) {
      printSessionError(e);
      return exitStatus(e.kind());
    }
    if (network.session) loop.add(*network.session);
    if (network.spectator) loop.add(*network.spectator);
  } else {
    loop.add(opponent);  // red's orders first, then the person's
    loop.add(mine);
  }

  // A network game ends after its agreed ticks (0: at once, as headless); a window alone runs until
  // closed unless --ticks says otherwise.
  auto gameOver = [&] { return (networked || o.ticks > 0) && game.tickCount() >= unsigned(o.ticks); };
  bool over = gameOver();
  try {
    while (leftWhile.empty() && !quit && !over) {
      ++frame;
      for (; nextScripted < script.size() && script[nextScripted].frame <= frame; ++nextScripted) {
        for (int k = 0; k < script[nextScripted].count; ++k) SDL_PushEvent(&script[nextScripted].events[k]);
      }
      handleEvents();

      // Fixed ticks: as many as real time owes (at most a few per frame), or one per frame under a script.
      const auto now = Clock::now();
      owed += std::chrono::duration<double>(now - last).count();
      last = now;
      int due = script.empty() ? std::min(4, int(owed / Game::kTickSeconds)) : 1;
      owed = script.empty() ? std::min(owed - due * Game::kTickSeconds, Game::kTickSeconds) : 0;
      if (paused) due = 0;
      // A spectator that came in under way plays the game so far, and whatever the host sent while it
      // was slow, faster than the clock until it has caught up; a frame still comes every 25 ms or so.
      auto catchingUp = [&] {
        return network.spectator && script.empty() && network.spectator->ticksReceived() > 2 &&
               Clock::now() - now < std::chrono::milliseconds(25);
      };
      for (int t = 0; !quit && !over && (t < due || catchingUp()); ++t) {
        const std::vector<Command>& commands = loop.tick();
        // Recorded before the hashes are compared: a desync's replay holds the tick that differs.
        if (recorder) recorder->afterTick(game, commands);
        if (network.session) network.session->afterTick(game);
        if (network.spectator) network.spectator->afterTick(game);
        over = gameOver();
      }
      sceneOptions.banner = networked ? networkLine : "";
      if (!show(quit || over)) return 1;
    }
    if (!leftWhile.empty()) {
      // Left before the game began: nothing to finish.
    } else if (networked && over) {
      if (network.session) network.session->finish(game);
      if (network.spectator) network.spectator->finish(game);
    } else if (networked) {
      if (network.session) network.session->quit();
      if (network.spectator) network.spectator->quit();
      leftWhile = "you quit";
    }
  } catch (const net::LeftGame& e) {
    if (!leftWaiting(e)) return 1;
  } catch (const net::SessionError& e) {
    return endedEarly(e, game, o, recorder);
  }
  if (recorder) recorder->finish(game);
  printSummary(game, o, 0, 0, 0);
  if (!leftWhile.empty()) {
    std::printf("Network game left at tick %u: %s.\n", game.tickCount(), leftWhile.c_str());
  } else if (networked) {
    printNetworkEnd(network, game, o);
  }
  return 0;
}

}  // namespace rts
