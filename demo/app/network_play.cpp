#include "app/network_play.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "app/run.h"
#include "net/hello.h"
#include "tool/recorder.h"

namespace rts {
namespace {

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

}  // namespace

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

void printSessionError(const net::SessionError& e) {
  std::fprintf(stderr, "rattle-demo: %s\n%s", e.what(), e.details().c_str());
}

int endedEarly(const net::SessionError& e, const Game& game, const Options& o, replay::Recorder* recorder) {
  printSessionError(e);
  // The ticks played so far replay as they were: after a desync, what to compare with the peer's.
  if (recorder) {
    recorder->finish(game);
    std::fprintf(stderr, "rattle-demo: the %u ticks played are in the replay %s\n", game.tickCount(),
                 o.record.c_str());
  }
  return exitStatus(e.kind());
}

Network connectNetwork(Game& game, const Options& o, const std::string& mapJson, CommandSource& local,
                       std::function<bool(const std::string&, double)> whileWaiting) {
  // A line in the middle of the headless progress line would be lost at its end: start a line of its own.
  const bool newline = !o.window && !o.quiet && isatty(2);
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
  config.whileWaiting = std::move(whileWaiting);
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
  n.session = std::make_unique<net::LockstepSession>(*n.transport, local, std::move(config));
  n.session->handshake(game);
  n.start = std::chrono::steady_clock::now();
  say(std::string("playing ") + teamName(o.team()) + " against " + teamName(1 - o.team()) + ": input delay " +
      std::to_string(o.inputDelay) + " ticks, state hashes compared every " +
      (o.hashEvery == 1 ? std::string("tick") : std::to_string(o.hashEvery) + " ticks"));
  return n;
}

void printNetworkEnd(const Network& network, const Game& game, const Options& o) {
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
                 "rattle-demo: joined at tick %u (started from the host's state there, %zu bytes), %u state "
                 "hashes compared with the host's; waited %.2f s for the host in all\n",
                 network.spectator->joinedAt(), network.spectator->stateBytes(), network.spectator->hashesCompared(),
                 network.spectator->waitedSeconds());
    printTraffic(network, "the host", game.tickCount());
  }
}

}  // namespace rts
