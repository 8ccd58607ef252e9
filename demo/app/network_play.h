// What a networked game (--host, --join, --watch) is the same for headless and in the window: the
// connection and the handshake, the lines printed at its end, and how an early end is reported.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "app/options.h"
#include "game/commands.h"
#include "game/game.h"
#include "net/lockstep.h"
#include "net/spectator.h"
#include "net/transport.h"

namespace rts {
namespace replay {
class Recorder;
}

/// The network side of a game: the transport and the session (a player's or a spectator's), once the
/// handshake has passed.
struct Network {
  std::unique_ptr<net::Transport> transport;
  std::unique_ptr<net::LockstepSession> session;
  std::unique_ptr<net::SpectatorSession> spectator;
  std::chrono::steady_clock::time_point start;  // the handshake passed: the game's traffic from here on
};

/// "blue (team 0)" or "red (team 1)".
const char* teamName(int team);

/// Hosts, joins or watches as the options say and passes the handshake. `local` gives this side's
/// commands (not asked when watching); `whileWaiting` is LockstepConfig's (empty headless). Watching,
/// `game` takes the host's state (it is then at the tick the spectator joined). Throws
/// net::SessionError (and net::LeftGame when whileWaiting asks to leave, net::TransportError when the
/// port or the name will not do).
Network connectNetwork(Game& game, const Options& options, const std::string& mapJson, CommandSource& local,
                       std::function<bool(const std::string&, double)> whileWaiting = {});

/// rattle-demo's exit status for a game that ended early this way (app/run.h).
int exitStatus(net::SessionError::Kind kind);

/// Why a networked game ended early, on stderr: the line, and under it a desync's report.
void printSessionError(const net::SessionError& error);

/// A game that ended early after its handshake: says why (and a desync's report), finishes the replay with the ticks played
/// and says so, and returns the exit status.
int endedEarly(const net::SessionError& error, const Game& game, const Options& options, replay::Recorder* recorder);

/// After the last tick and the session's finish(): the line both sides print (stdout), how long this side
/// waited (stderr) and what the game cost the network (stdout).
void printNetworkEnd(const Network& network, const Game& game, const Options& options);

}  // namespace rts
