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
};

class Transport {
 public:
  /// Listens on `port` (0: a free one, see localPort()) on every interface, for one peer.
  /// Throws TransportError naming the port when it cannot.
  static std::unique_ptr<Transport> host(uint16_t port);
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
  /// Refuse must reach it), then disconnects at once. Packets that arrive meanwhile are dropped.
  void close(double lingerSeconds);

 private:
  struct Impl;
  explicit Transport(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace rts::net
