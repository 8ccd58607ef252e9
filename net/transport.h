// The network under a lockstep game: one ENet connection between two processes, carrying one protocol
// message (net/protocol.h) a packet, reliably and in order on one channel.
//
// Only decoded messages come out of here. What ENet does with time (resends, pings, when a packet
// arrives) decides when a message is seen, never what it says, and the lockstep session decides what
// a message means from its contents alone (its tick), so no timing reaches the game.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "net/protocol.h"

namespace rts::net {

/// The port --host listens on and --join connects to when none is given.
inline constexpr uint16_t kDefaultPort = 47800;

/// The transport cannot be set up: the port is taken, the host name does not resolve, ENet fails.
class TransportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What one poll saw.
struct TransportEvent {
  enum class Kind {
    None,          ///< nothing within the timeout
    Connected,     ///< the peer connected (host) or the connection was accepted (joiner)
    Received,      ///< a packet that decoded: `message`
    Garbage,       ///< a packet that did not decode: `error` is decode's line
    Disconnected,  ///< the peer left, ENet gave up on it, or (joiner) it could not be reached
  };
  Kind kind = Kind::None;
  std::optional<Message> message;
  std::string error;
  /// A host's second connection, the spectator's, rather than the player's (Transport::host with a
  /// spectator slot). Connected, Received, Garbage and Disconnected come for it too.
  bool spectator = false;
};

/// What went over one connection: the protocol's messages (a packet each) and their bytes, as the
/// session sent and received them (ENet's headers, acknowledgements and resends not counted).
struct LinkCounts {
  uint64_t messagesSent = 0, bytesSent = 0;
  uint64_t messagesReceived = 0, bytesReceived = 0;
};

/// What this process's UDP socket carried: every datagram ENet sent and received, its headers,
/// acknowledgements, pings and resends included, to and from every peer.
struct SocketCounts {
  uint64_t datagramsSent = 0, bytesSent = 0;
  uint64_t datagramsReceived = 0, bytesReceived = 0;
};

class Transport {
 public:
  /// Listens on `port` (0: a free one, see localPort()) on every interface, for one peer, and with
  /// `spectatorSlot` for one more while the first is connected: the spectator's (its events come with
  /// `spectator` set). A connection beyond those is turned away. Throws TransportError naming the port
  /// when it cannot.
  static std::unique_ptr<Transport> host(uint16_t port, bool spectatorSlot = false);
  /// Starts connecting to hostName:port; poll() reports Connected or Disconnected. Throws
  /// TransportError when the name does not resolve.
  static std::unique_ptr<Transport> join(const std::string& hostName, uint16_t port);

  ~Transport();
  Transport(const Transport&) = delete;
  Transport& operator=(const Transport&) = delete;

  /// The UDP port this side is bound to.
  uint16_t localPort() const;
  /// Whether a peer is connected now.
  bool connected() const;

  /// How long ENet itself keeps trying to reach a peer that does not answer before it reports
  /// Disconnected (for a joiner: how long the connection attempt lasts). Applies to the peer now
  /// connected or being connected to, and to a peer that connects later.
  void setPeerTimeout(double seconds);

  /// Sends a message reliably (encode() may throw std::invalid_argument). Nothing happens without a
  /// connected peer: the caller learns of the disconnect from poll().
  void send(const Message& message);
  /// Sends bytes as one packet, as they are: for tests of a peer that sends garbage.
  void sendBytes(const std::vector<uint8_t>& bytes);

  /// Waits up to `timeoutSeconds` (0: only what has already arrived) for one event. Packets are
  /// decoded with `context`. A second peer connecting to a host is turned away and not reported.
  TransportEvent poll(double timeoutSeconds, const DecodeContext& context);

  /// Leaves: waits up to `lingerSeconds` for the peer to acknowledge every message sent (the last Bye or
  /// Refuse must reach it), then disconnects at once. Packets that arrive meanwhile are dropped. The
  /// spectator, when there is one, stays connected (closeSpectator).
  void close(double lingerSeconds);

  /// A host whose first peer turned out not to be a player (a spectator that came too early): after
  /// close(), takes the next one that connects as its peer.
  void acceptAnotherPeer();

  // ---- The spectator's connection (a host with a spectator slot) ----

  bool spectatorConnected() const;
  /// Sends a message to the spectator reliably; nothing happens without one.
  void sendToSpectator(const Message& message);
  /// Messages sent to the spectator and not yet acknowledged: how far behind it is.
  size_t spectatorBacklog() const;
  /// As close(), for the spectator's connection only; the slot is then free for another.
  void closeSpectator(double lingerSeconds);

  // ---- Counts, for the bandwidth a game takes ----

  const LinkCounts& peerCounts() const;       ///< the player's connection (a joiner's, the host's)
  const LinkCounts& spectatorCounts() const;  ///< every spectator's connection so far, summed
  SocketCounts socketCounts() const;

 private:
  struct Impl;
  explicit Transport(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace rts::net
