// A bad network for the tests (issue 26, point 7): a UDP relay between a joiner and a host that forwards
// datagrams both ways and on the way drops some, sends some twice, holds some back behind later ones,
// and delays every one by a jitter. ENet's reliable channel carries the lockstep messages through it, so
// a game must come out the same with it as without it: the relay may change when a message arrives,
// never what it says.
//
// Its choices come from a seeded generator, one stream each way, with the same number of draws for every
// datagram: the n-th datagram each way meets the same fate in every run with the same seed. Which
// datagram is the n-th depends on ENet's timing (its resends, acknowledgements and pings), so a run is
// reproducible in what the relay does to each stream, not in which packets it does it to.
//
// One joiner: the first address that sends to the relay's port is the joiner, and datagrams from any
// other address are dropped (and counted as strangers). IPv4, as ENet.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

namespace rts::net {

/// What the relay does to each datagram, each way. The defaults are issue 26's: 10% lost, 5% sent
/// twice, 5% held back, 50 to 200 ms of delay.
struct FaultModel {
  uint64_t seed = 26;
  double drop = 0.10;              ///< the probability a datagram is lost
  double duplicate = 0.05;         ///< the probability it is sent twice (the copy with a delay of its own)
  double reorder = 0.05;           ///< the probability it is held back until the next datagram that way has gone
  double minDelaySeconds = 0.050;  ///< every datagram (and copy) waits uniformly between these two
  double maxDelaySeconds = 0.200;
};

/// What the relay did one way.
struct RelayCounts {
  uint64_t received = 0;    ///< datagrams that came in
  uint64_t dropped = 0;     ///< of those, lost on purpose
  uint64_t duplicated = 0;  ///< sent twice
  uint64_t heldBack = 0;    ///< held until a later one had gone
  uint64_t sent = 0;        ///< datagrams that went out (copies counted)
  uint64_t strangers = 0;   ///< (towards the host) from an address other than the joiner's: ignored
};

class FaultyRelay {
 public:
  /// Binds UDP `listenPort` on every interface (0: a free one, see port()) and resolves the host. Throws
  /// std::runtime_error naming the port or the host when it cannot, or when the model is not one (a
  /// probability outside 0 to 1, delays not 0 <= min <= max <= 10 s).
  FaultyRelay(uint16_t listenPort, const std::string& hostName, uint16_t hostPort, const FaultModel& model);
  /// Stops forwarding.
  ~FaultyRelay();
  FaultyRelay(const FaultyRelay&) = delete;
  FaultyRelay& operator=(const FaultyRelay&) = delete;

  /// The port a joiner connects to.
  uint16_t port() const;
  /// Starts forwarding on a thread of its own. Datagrams that came before wait in the socket.
  void start();
  /// Stops the thread; what is still delayed is dropped. Idempotent.
  void stop();

  RelayCounts towardsHost() const;
  RelayCounts towardsJoiner() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rts::net
