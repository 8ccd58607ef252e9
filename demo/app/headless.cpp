// Headless: the scripted opponent plays both teams, or with --host / --join this side's team against the
// peer's over the network; every N ticks a frame is drawn offscreen and saved.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string_view>

#include "app/run.h"
#include "game/opponent.h"
#include "game/tick_loop.h"
#include "net/hello.h"
#include "net/lockstep.h"
#include "net/spectator.h"
#include "net/transport.h"
#include "render/offscreen.h"
#include "render/png.h"
#include "render/scene_builder.h"
#include "tool/recorder.h"

namespace rts {
namespace {

// frame_ and six or more digits and .png: exactly the names frame() below writes, nothing a person named.
bool isFrameName(const std::string& name) {
  constexpr std::string_view prefix = "frame_", suffix = ".png";
  if (name.size() < prefix.size() + 6 + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
    return false;
  }
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  return std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// A shorter or sparser run into the same directory would leave an earlier game's frames between this
// one's, and a glob over the directory (frame_*.png into ffmpeg) would mix the two games.
bool removeEarlierFrames(const std::string& dir) {
  std::error_code ec;
  size_t removed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file(ec) || !isFrameName(entry.path().filename().string())) continue;
    if (!std::filesystem::remove(entry.path(), ec)) {
      std::fprintf(stderr, "rattle-demo: --frames %s: cannot remove the earlier frame %s (%s)\n", dir.c_str(),
                   entry.path().filename().string().c_str(), ec.message().c_str());
      return false;
    }
    ++removed;
  }
  if (ec) {
    std::fprintf(stderr, "rattle-demo: --frames %s: cannot list the directory (%s)\n", dir.c_str(), ec.message().c_str());
    return false;
  }
  if (removed) std::fprintf(stderr, "rattle-demo: removed %zu frame_NNNNNN.png files of an earlier run from %s\n", removed, dir.c_str());
  return true;
}

const char* teamName(int team) { return team == 0 ? "blue (team 0)" : "red (team 1)"; }

int exitStatus(net::SessionError::Kind kind) {
  switch (kind) {
    case net::SessionError::Kind::Refused: return kExitRefused;
    case net::SessionError::Kind::Desync: return kExitDesync;
    case net::SessionError::Kind::PeerLost: return kExitPeerLost;
    case net::SessionError::Kind::Protocol: return kExitProtocol;
  }
  return 1;
}

// Why a networked game ended early: the line, and under it a desync's report (the bodies and fields that
// differ, as rattle-replay verify names them; net/desync_report.h).
void printSessionError(const net::SessionError& e) {
  std::fprintf(stderr, "rattle-demo: %s\n%s", e.what(), e.details().c_str());
}

// The network side of a headless run: the transport and the session (a player's or a spectator's),
// once the handshake has passed.
struct Network {
  std::unique_ptr<net::Transport> transport;
  std::unique_ptr<net::LockstepSession> session;
  std::unique_ptr<net::SpectatorSession> spectator;
  std::chrono::steady_clock::time_point start;  // the handshake passed: the game's traffic from here on
};

std::string perSecond(uint64_t bytes, uint64_t packets, double seconds, const char* unit) {
  char text[200];
  std::snprintf(text, sizeof text, "%llu bytes in %llu %s (%.0f bytes/s, %.1f %s/s)",
                static_cast<unsigned long long>(bytes), static_cast<unsigned long long>(packets), unit,
                bytes / seconds, packets / seconds, unit);
  return text;
}

// What the game cost the network, for net/README.md's figures: the protocol's messages to and from each
// connection, and what the socket carried with ENet's own traffic (headers, acknowledgements, pings and
// resends, to and from every connection). From the handshake's end to the game's, per second of game
// time (30 ticks): a headless game plays as fast as the peer allows, a game in a window at 30 ticks a
// second, so rates by the wall clock would say nothing about the latter.
void printTraffic(const Network& n, const char* peerName, uint32_t ticks) {
  const double gameSeconds = std::max(1u, ticks) * Game::kTickSeconds;
  const double wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - n.start).count();
  const net::LinkCounts& p = n.transport->peerCounts();
  std::printf("Network traffic over %u ticks (%.1f s of game time; %.1f s by the clock), per second of game time: "
              "messages to %s %s; from %s %s.\n",
              ticks, gameSeconds, wallSeconds, peerName,
              perSecond(p.bytesSent, p.messagesSent, gameSeconds, "messages").c_str(), peerName,
              perSecond(p.bytesReceived, p.messagesReceived, gameSeconds, "messages").c_str());
  if (n.session && n.session->spectatorsServed() > 0) {
    const net::LinkCounts& w = n.transport->spectatorCounts();
    std::printf("To the spectator (%u served): %s; from it %s.\n", n.session->spectatorsServed(),
                perSecond(w.bytesSent, w.messagesSent, gameSeconds, "messages").c_str(),
                perSecond(w.bytesReceived, w.messagesReceived, gameSeconds, "messages").c_str());
  }
  const net::SocketCounts u = n.transport->socketCounts();
  std::printf("UDP socket, ENet's headers, acknowledgements, pings and resends included: sent %s; received %s.\n",
              perSecond(u.bytesSent, u.datagramsSent, gameSeconds, "datagrams").c_str(),
              perSecond(u.bytesReceived, u.datagramsReceived, gameSeconds, "datagrams").c_str());
}

Network connect(const Game& game, const Options& o, const std::string& mapJson, CommandSource& opponent) {
  // A line in the middle of the progress line would be lost at its end: start a line of its own.
  const bool newline = !o.quiet && isatty(2);
  auto say = [newline](const std::string& line) {
    std::fprintf(stderr, "%srattle-demo: %s\n", newline ? "\n" : "", line.c_str());
  };
  Network n;
  if (o.network == Options::Network::Host) {
    n.transport = net::Transport::host(o.port, true);
    say("hosting on UDP port " + std::to_string(n.transport->localPort()) +
        ", waiting for a player to join (rattle-demo --join THIS-HOST:" + std::to_string(n.transport->localPort()) +
        " with the same options)");
  } else {
    n.transport = net::Transport::join(o.joinHost, o.port);
    say(std::string(o.network == Options::Network::Watch ? "watching " : "joining ") + o.joinHost + ":" +
        std::to_string(o.port));
  }
  net::LockstepConfig config;
  config.peerTimeoutSeconds = o.peerTimeout;
  config.log = say;
  if (o.network == Options::Network::Watch) {
    config.hello = net::spectatorHello(game, mapJson, o.seed, uint16_t(o.inputDelay), uint16_t(o.hashEvery),
                                       uint32_t(o.ticks));
    n.spectator = std::make_unique<net::SpectatorSession>(*n.transport, std::move(config));
    n.spectator->handshake(game);
    n.start = std::chrono::steady_clock::now();
    return n;
  }
  config.hello = net::playerHello(game, mapJson, o.seed, uint8_t(o.team()), uint16_t(o.inputDelay),
                                  uint16_t(o.hashEvery), uint32_t(o.ticks));
  config.acceptSpectator = o.network == Options::Network::Host;
  n.session = std::make_unique<net::LockstepSession>(*n.transport, opponent, std::move(config));
  n.session->handshake(game);
  n.start = std::chrono::steady_clock::now();
  say(std::string("playing ") + teamName(o.team()) + " against " + teamName(1 - o.team()) + ": input delay " +
      std::to_string(o.inputDelay) + " ticks, state hashes compared every " +
      (o.hashEvery == 1 ? std::string("tick") : std::to_string(o.hashEvery) + " ticks"));
  return n;
}

}  // namespace

int runHeadless(Game& game, const Options& o, const std::string& mapJson, replay::Recorder* recorder) {
  std::unique_ptr<OffscreenRenderer> renderer;
  if (o.render) {
    std::error_code ec;
    std::filesystem::create_directories(o.framesDir, ec);
    if (ec) {
      std::fprintf(stderr, "rattle-demo: --frames %s: cannot create the directory (%s)\n", o.framesDir.c_str(), ec.message().c_str());
      return 1;
    }
    if (!removeEarlierFrames(o.framesDir)) return 1;
    renderer = std::make_unique<OffscreenRenderer>(o.width, o.height, o.supersample);
  }
  const bool networked = o.network != Options::Network::None;
  // Networked, each side's opponent plays its own team only; its commands reach the game through the
  // session, which applies both teams' in one order on both sides.
  ScriptedOpponent opponent(o.seed, networked ? 1u << o.team() : 3u);  // not asked when watching
  TickLoop loop(game);
  Network network;
  if (networked) {
    try {
      network = connect(game, o, mapJson, opponent);
    } catch (const net::SessionError& e) {
      printSessionError(e);
      return exitStatus(e.kind());
    }
    if (network.session) {
      loop.add(*network.session);
    } else {
      loop.add(*network.spectator);
    }
  } else {
    loop.add(opponent);
  }
  std::vector<double> frameSeconds, drawSeconds;
  int frames = 0;
  SceneOptions view;
  view.fogTeam = o.fogTeam;
  view.showSight = o.showSight;
  view.showTimes = o.showTimes;

  auto frame = [&]() -> bool {
    const auto start = std::chrono::steady_clock::now();
    char name[64];
    std::snprintf(name, sizeof name, "/frame_%06u.png", game.tickCount());
    const std::string path = o.framesDir + name;
    const std::vector<uint8_t>& pixels = renderer->render(buildScene(game, view));
    drawSeconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    const std::string error = writePng(path, o.width, o.height, pixels);
    if (!error.empty()) {
      std::fprintf(stderr, "\nrattle-demo: %s\n", error.c_str());
      return false;
    }
    ++frames;
    frameSeconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return true;
  };

  if (renderer && !frame()) return 1;
  try {
    for (long t = 0; t < o.ticks; ++t) {
      const std::vector<Command>& commands = loop.tick();
      // Recorded before the hashes are compared: a desync's replay holds the tick that differs.
      if (recorder) recorder->afterTick(game, commands);
      if (network.session) network.session->afterTick(game);
      if (network.spectator) network.spectator->afterTick(game);
      if (renderer && game.tickCount() % unsigned(o.every) == 0 && !frame()) return 1;
      if (!o.quiet) progress(game, o.ticks, false);
    }
    if (network.session) network.session->finish(game);
    if (network.spectator) network.spectator->finish(game);
  } catch (const net::SessionError& e) {
    if (!o.quiet) progress(game, o.ticks, true);
    printSessionError(e);
    // The ticks played so far replay as they were: after a desync, what to compare with the peer's.
    if (recorder) {
      recorder->finish(game);
      std::fprintf(stderr, "rattle-demo: the %u ticks played are in the replay %s\n", game.tickCount(),
                   o.record.c_str());
    }
    return exitStatus(e.kind());
  }
  if (!o.quiet) progress(game, o.ticks, true);
  if (recorder) recorder->finish(game);
  std::sort(frameSeconds.begin(), frameSeconds.end());
  std::sort(drawSeconds.begin(), drawSeconds.end());
  printSummary(game, o, frames, frameSeconds.empty() ? 0 : frameSeconds[frameSeconds.size() / 2],
               drawSeconds.empty() ? 0 : drawSeconds[drawSeconds.size() / 2]);
  if (network.session) {
    // The same line on both sides (a test compares them); the waiting differs, so it goes elsewhere.
    std::printf("Network game over after %u ticks: final state hash %016llx, the same on both sides.\n",
                game.tickCount(), static_cast<unsigned long long>(game.stateHash()));
    std::fprintf(stderr,
                 "rattle-demo: %u state hashes compared with the peer's; waited %.2f s for %s in all, at most "
                 "%.2f s at once\n",
                 network.session->hashesCompared(), network.session->waitedSeconds(), teamName(1 - o.team()),
                 network.session->longestWaitSeconds());
    printTraffic(network, "the peer", game.tickCount());
  }
  if (network.spectator) {
    std::printf("Network game over after %u ticks: final state hash %016llx, the same as the host's.\n",
                game.tickCount(), static_cast<unsigned long long>(game.stateHash()));
    std::fprintf(stderr,
                 "rattle-demo: joined at tick %u (the state compared in full there), %u state hashes compared "
                 "with the host's; waited %.2f s for the host in all\n",
                 network.spectator->joinedAt(), network.spectator->hashesCompared(),
                 network.spectator->waitedSeconds());
    printTraffic(network, "the host", game.tickCount());
  }
  return 0;
}

}  // namespace rts
