#include "app/options.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>

namespace rts {
namespace {

const char* kUsage =
    "usage: rattle-demo [options]\n"
    "\n"
    "An RTS arena on the rattle collision engine: two teams played by a scripted opponent from a seed,\n"
    "walls, buildings, doorways, a gate, sight sensors and projectiles. Headless by default: it writes PNG\n"
    "frames drawn offscreen with OSMesa. With --window it opens an SDL2 window you can play in: blue against\n"
    "the scripted opponent, or with --host or --join your side's team against another player.\n"
    "\n"
    "  --map FILE      Tiled JSON map (default: assets/maps/arena.json)\n"
    "  --ticks N       ticks to run, 30 per second (default 600); with --window, quit after N (default: never;\n"
    "                  in a network game 600 as headless: both sides play the same number of ticks)\n"
    "  --seed N        seed of the scripted opponent, 0 to 2^64-1 (default 1)\n"
    "  --units N       units per team, 1 to 200000 (default 100)\n"
    "  --frames DIR    where frames go (default out/demo), as frame_NNNNNN.png by tick; the frame_NNNNNN.png\n"
    "                  files already in DIR (an earlier run's) are removed first, nothing else there\n"
    "  --every N       write a frame every N ticks (default 10)\n"
    "  --size WxH      frame or window size in pixels (default 1280x720)\n"
    "  --supersample N draw N x N samples per pixel for smooth edges, 1 to 4 (default 2; 1 in the window)\n"
    "  --no-render     draw nothing: the game and the engine only (for timing)\n"
    "  --fog TEAM      whose fog of war the frames show: 0 (blue, default), 1 (red) or none\n"
    "  --no-sight      do not draw the sight range outlines\n"
    "  --no-times      leave the measured step time out of the HUD, so the same input gives the same\n"
    "                  frames byte for byte\n"
    "  --mode M        engine step mode: hybrid (default), discrete (step-and-check: watch projectiles go\n"
    "                  through walls and count as 'ran out of range'), predictive (event-driven\n"
    "                  throughout; sensor events are found along the paths after each step)\n"
    "  --steering S    how units are steered: keep-apart (default: units keep apart, queue and wait for\n"
    "                  gaps; demo/README.md, \"Crowds\") or naive (every unit with an order goes at full speed\n"
    "                  toward its target and is pushed into whatever is in the way: a crowd the engine has to\n"
    "                  keep apart). Not with --record: a replay plays the default steering\n"
    "  --window        open a window: left-drag selects your units (blue, or your side's in a network game),\n"
    "                  right-click moves them, space pauses (not a network game), v toggles sight ranges,\n"
    "                  g works the first gate, f changes the fog (not a network player: it keeps its own\n"
    "                  team's), Esc or q quits (a network game: leaves it, telling the peer)\n"
    "  --screenshot F  with --window: save the last frame shown as PNG file F when the window closes\n"
    "  --input FILE    with --window: play the scripted input events in FILE (see demo/README.md)\n"
    "  --record FILE   record the game as a replay in FILE (headless or --window): the map, the\n"
    "                  commands at their ticks, the state hash of every tick; check or draw it again with\n"
    "                  build/bin/rattle-replay verify|render FILE (replay/README.md). Recording changes\n"
    "                  nothing in the game\n"
    "  --keyframe-every K  with --record: every body's exact state every K ticks (default 30)\n"
    "  --quiet         no progress line\n"
    "  --help          this text\n"
    "\n"
    "Network play (demo/README.md, \"Network play\"): two rattle-demo processes play one game in lockstep\n"
    "over ENet, each side's team played by its scripted opponent, or with --window by you, and a third\n"
    "may watch (in a window too). All must be given the same --map, --seed, --units, --mode, --steering,\n"
    "--ticks, --input-delay and --hash-every: the handshake compares them and refuses a difference. In a\n"
    "window, while the game waits for the peer it says whom it waits for and how long.\n"
    "  --host [PORT]   host the game on UDP port PORT (default 47800; 0: any free port, printed) and play\n"
    "                  blue (team 0); waits for a player to join, then takes one spectator at a time\n"
    "  --join HOST[:PORT]  join the game hosted at HOST (a name or an IPv4 address; port default 47800)\n"
    "                  and play red (team 1)\n"
    "  --watch HOST[:PORT]  watch the game hosted at HOST, from any tick once a player has joined: it starts\n"
    "                  from the host's state a few ticks later, then follows; sends no commands, is never\n"
    "                  waited for, and checks its state hashes against the host's (not with --record)\n"
    "  --input-delay N ticks between issuing a command and applying it, 0 to 300 (default 3: 100 ms of\n"
    "                  round trip at 30 ticks a second)\n"
    "  --hash-every K  compare the state hash with the peer's every K ticks, 1 to 65535 (default 1)\n"
    "  --peer-timeout S  give up on a peer silent for S seconds, 0.1 to 3600 (default 10)\n"
    "  With --host, --join or --watch, frames go to out/demo-host, out/demo-join or out/demo-watch, and they\n"
    "  and the window show this side's fog (a spectator's: none) unless --frames and --fog say otherwise.\n"
    "  Exit status: 0 the game was played to the end with equal hashes, or you quit it in a window (the\n"
    "  peer is told), 3 the handshake refused the game, 4 desync (the state hashes differ),\n"
    "  5 the peer could not be reached, disconnected, went silent or left early (a spectator's peer is the\n"
    "  host), 6 the peer sent garbage or broke the protocol.\n"
    "\n"
    "Exit status: 0 done, 1 an error (a bad map, a file that cannot be written), 2 bad options; with\n"
    "--host, --join or --watch also 3 to 6 (above).\n";

bool parseLong(const char* text, long lo, long hi, long& out) {
  if (!text || !*text) return false;
  errno = 0;
  char* end = nullptr;
  long v = std::strtol(text, &end, 10);
  if (errno || *end != '\0' || v < lo || v > hi) return false;
  out = v;
  return true;
}

}  // namespace

ParseResult parseOptions(int argc, char** argv) {
  ParseResult r;
  Options& o = r.options;
  bool keyframeGiven = false;
  std::string networkOption;  // the last of the options that need --host or --join
  auto fail = [&](const std::string& message) {
    std::fprintf(stderr, "rattle-demo: %s\nTry 'rattle-demo --help'.\n", message.c_str());
    r.action = ParseResult::Action::Exit;
    r.exitCode = 2;
    return r;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    const char* lastValue = nullptr;
    auto value = [&]() -> const char* { return lastValue = i + 1 < argc ? argv[++i] : nullptr; };
    auto number = [&](long lo, long hi, long& out) -> bool {
      const char* v = value();
      if (!v) return false;
      return parseLong(v, lo, hi, out);
    };
    auto badNumber = [&](long lo, long hi) {
      return fail(std::string(arg) + " " + (lastValue ? lastValue : "(missing)") + ": expected a whole number from " + std::to_string(lo) + " to " +
                  std::to_string(hi));
    };
    long n = 0;
    if (arg == "--help" || arg == "-h") {
      std::fputs(kUsage, stdout);
      r.action = ParseResult::Action::Exit;
      r.exitCode = 0;
      return r;
    } else if (arg == "--map") {
      const char* v = value();
      if (!v || !*v) return fail("--map: expected a file name");
      o.map = v;
    } else if (arg == "--ticks") {
      if (!number(0, 100'000'000, n)) return badNumber(0, 100'000'000);
      o.ticks = n;
      o.ticksGiven = true;
    } else if (arg == "--seed") {
      const char* v = value();
      char* end = nullptr;
      errno = 0;
      unsigned long long s = v && *v && *v != '-' ? std::strtoull(v, &end, 10) : 0;
      if (!v || !*v || *v == '-' || errno || *end != '\0') {
        return fail(std::string("--seed ") + (v ? v : "(missing)") + ": expected a whole number from 0 to 18446744073709551615");
      }
      o.seed = s;
    } else if (arg == "--units") {
      if (!number(1, 200'000, n)) return badNumber(1, 200'000);
      o.units = int(n);
    } else if (arg == "--frames") {
      const char* v = value();
      if (!v || !*v) return fail("--frames: expected a directory");
      o.framesDir = v;
      o.framesGiven = true;
    } else if (arg == "--every") {
      if (!number(1, 100'000'000, n)) return badNumber(1, 100'000'000);
      o.every = int(n);
    } else if (arg == "--supersample") {
      if (!number(1, 4, n)) return badNumber(1, 4);
      o.supersample = int(n);
      o.supersampleGiven = true;
    } else if (arg == "--size") {
      const char* v = value();
      const char* x = v ? std::strchr(v, 'x') : nullptr;
      long w = 0, h = 0;
      if (!x || !parseLong(std::string(v, x).c_str(), 16, 8192, w) || !parseLong(x + 1, 16, 8192, h)) {
        return fail(std::string("--size ") + (v ? v : "(missing)") + ": expected WIDTHxHEIGHT, each 16 to 8192 (e.g. 1280x720)");
      }
      o.width = int(w);
      o.height = int(h);
    } else if (arg == "--no-render") {
      o.render = false;
    } else if (arg == "--fog") {
      const char* v = value();
      std::string_view f = v ? v : "";
      o.fogGiven = true;
      if (f == "0" || f == "blue") {
        o.fogTeam = 0;
      } else if (f == "1" || f == "red") {
        o.fogTeam = 1;
      } else if (f == "none") {
        o.fogTeam = -1;
      } else {
        return fail(std::string("--fog ") + (v ? v : "(missing)") + ": expected 0, 1 or none");
      }
    } else if (arg == "--no-sight") {
      o.showSight = false;
    } else if (arg == "--no-times") {
      o.showTimes = false;
    } else if (arg == "--mode") {
      const char* v = value();
      std::string_view m = v ? v : "";
      if (m == "hybrid") {
        o.mode = rattle::StepMode::Hybrid;
      } else if (m == "discrete") {
        o.mode = rattle::StepMode::Discrete;
      } else if (m == "predictive") {
        o.mode = rattle::StepMode::Predictive;
      } else {
        return fail(std::string("--mode ") + (v ? v : "(missing)") + ": expected hybrid, discrete or predictive");
      }
    } else if (arg == "--steering") {
      const char* v = value();
      std::string_view m = v ? v : "";
      if (m == "keep-apart") {
        o.steering = Steering::KeepApart;
      } else if (m == "naive") {
        o.steering = Steering::Naive;
      } else {
        return fail(std::string("--steering ") + (v ? v : "(missing)") + ": expected keep-apart or naive");
      }
    } else if (arg == "--window") {
      o.window = true;
    } else if (arg == "--screenshot") {
      const char* v = value();
      if (!v || !*v) return fail("--screenshot: expected a file name");
      o.screenshot = v;
    } else if (arg == "--input") {
      const char* v = value();
      if (!v || !*v) return fail("--input: expected a file name");
      o.inputScript = v;
    } else if (arg == "--record") {
      const char* v = value();
      if (!v || !*v) return fail("--record: expected a file name");
      o.record = v;
    } else if (arg == "--keyframe-every") {
      if (!number(1, 100'000'000, n)) return badNumber(1, 100'000'000);
      o.keyframeEvery = int(n);
      keyframeGiven = true;
    } else if (arg == "--host") {
      if (o.network != Options::Network::None) return fail("--host: a side either hosts, joins or watches, once");
      o.network = Options::Network::Host;
      // The port is optional: what follows is an option unless it is a number (a negative one too, to
      // be refused as a port rather than taken for an unknown option).
      const auto numberNext = [&] {
        const char* next = argv[i + 1];
        return next[0] != '-' || (next[1] >= '0' && next[1] <= '9');
      };
      if (i + 1 < argc && numberNext()) {
        if (!number(0, 65535, n)) return fail(std::string("--host ") + lastValue + ": expected a port from 0 to 65535");
        o.port = uint16_t(n);
      }
    } else if (arg == "--join" || arg == "--watch") {
      if (o.network != Options::Network::None) {
        return fail(std::string(arg) + ": a side either hosts, joins or watches, once");
      }
      o.network = arg == "--join" ? Options::Network::Join : Options::Network::Watch;
      const char* v = value();
      const std::string_view text = v ? v : "";
      const size_t colon = text.find(':');
      o.joinHost = std::string(text.substr(0, colon));
      if (o.joinHost.empty() ||
          (colon != std::string_view::npos && text.find(':', colon + 1) != std::string_view::npos)) {
        return fail(std::string(arg) + " " + (v ? v : "(missing)") +
                    ": expected HOST or HOST:PORT (a name or an IPv4 address)");
      }
      if (colon != std::string_view::npos) {
        if (!parseLong(std::string(text.substr(colon + 1)).c_str(), 1, 65535, n)) {
          return fail(std::string(arg) + " " + v + ": the port after ':' must be a whole number from 1 to 65535");
        }
        o.port = uint16_t(n);
      }
    } else if (arg == "--input-delay") {
      if (!number(0, net::kMaxInputDelayTicks, n)) return badNumber(0, net::kMaxInputDelayTicks);
      o.inputDelay = int(n);
      networkOption = arg;
    } else if (arg == "--hash-every") {
      if (!number(1, 65535, n)) return badNumber(1, 65535);
      o.hashEvery = int(n);
      networkOption = arg;
    } else if (arg == "--peer-timeout") {
      const char* v = value();
      char* end = nullptr;
      errno = 0;
      const double s = v && *v ? std::strtod(v, &end) : 0;
      if (!v || !*v || errno || *end != '\0' || !(s >= 0.1 && s <= 3600)) {
        return fail(std::string("--peer-timeout ") + (v ? v : "(missing)") + ": expected seconds from 0.1 to 3600");
      }
      o.peerTimeout = s;
      networkOption = arg;
    } else if (arg == "--quiet") {
      o.quiet = true;
    } else {
      return fail("unknown option '" + std::string(arg) + "'");
    }
  }
  if (!o.window && (!o.screenshot.empty() || !o.inputScript.empty())) {
    return fail(std::string(o.screenshot.empty() ? "--input" : "--screenshot") + " needs --window");
  }
  if (o.window && !o.render) return fail("--window and --no-render cannot go together");
  if (keyframeGiven && o.record.empty()) return fail("--keyframe-every needs --record");
  if (o.steering != Steering::KeepApart && !o.record.empty()) {
    return fail("--steering naive cannot go with --record: a replay does not record the steering, and is played "
                "with the default (keep-apart)");
  }
  if (o.network == Options::Network::Watch && !o.record.empty()) {
    return fail(
        "--watch cannot go with --record: a spectator starts from the host's state under way, and a "
        "replay starts at tick 0 (record on the host's or the joiner's side)");
  }
  if (o.network != Options::Network::None) {
    // Two sides on one machine would otherwise write over each other's frames.
    if (!o.framesGiven) {
      o.framesDir = o.network == Options::Network::Host   ? "out/demo-host"
                    : o.network == Options::Network::Join ? "out/demo-join"
                                                          : "out/demo-watch";
    }
    if (!o.fogGiven) o.fogTeam = o.network == Options::Network::Watch ? -1 : o.team();
    // A player sees what its own units see, as the peer does: another fog would show the other side.
    if (o.network != Options::Network::Watch && o.fogTeam != o.team()) {
      return fail(std::string("--fog ") + (o.fogTeam < 0 ? "none" : std::to_string(o.fogTeam)) +
                  ": a player in a network game sees its own team's fog only (" + std::to_string(o.team()) +
                  " here); --watch may show any");
    }
  } else if (!networkOption.empty()) {
    return fail(networkOption + " needs --host, --join or --watch");
  }
  return r;
}

}  // namespace rts
