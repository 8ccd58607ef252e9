#include "net/transport.h"

#include <enet/enet.h>
#include <enet/time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>

namespace rts::net {
namespace {

// enet_initialize once per process, before the first host, and enet_deinitialize at exit. A function's
// static is made once even when two threads (the tests' two peers) reach it together.
void initializeEnet() {
  struct Library {
    Library() {
      if (enet_initialize() != 0) throw TransportError("cannot initialize ENet");
    }
    ~Library() { enet_deinitialize(); }
  };
  static const Library library;
}

enet_uint32 milliseconds(double seconds) {
  if (!(seconds > 0)) return 0;
  return enet_uint32(std::min(std::ceil(seconds * 1000), 86'400'000.0));
}

// ENet's limits for this host. A packet is one message, so nothing bigger than the protocol's packet
// is reassembled; what waits undelivered is bounded by the lockstep session, which never lets a peer
// run more than a few input delays ahead.
void limit(ENetHost* host) {
  host->maximumPacketSize = kMaxPacketBytes;
  host->maximumWaitingData = 8 * kMaxPacketBytes;
}

// ENet doubles a reliable packet's resend timeout each time it resends it, with no ceiling but the
// disconnect. On a link that loses one datagram in ten, one packet in some ten thousand is lost four
// times running, and then 1 + 2 + 4 + 8 times the first timeout pass before it arrives: the faulty
// relay's test (net/tests/test_net_relay.cpp) saw stalls of 15 s, and a peer taken for silent. Every
// message of a lockstep game is awaited, and on one channel in order, so a late resend stalls the game
// for that long: the timeout is held to twice the first one (ENet's round trip plus four deviations),
// within these bounds. It changes when a packet is resent, never what arrives.
constexpr enet_uint32 kMinResendCapMs = 200;
constexpr enet_uint32 kMaxResendCapMs = 2000;

// The fields are ENet's public ones (enet.h), as close() below reads; ENet reads them back when it next
// checks for lost packets.
void capResendTimeouts(ENetPeer* peer) {
  const enet_uint32 cap = std::clamp<enet_uint32>(2 * (peer->roundTripTime + 4 * peer->roundTripTimeVariance),
                                                  kMinResendCapMs, kMaxResendCapMs);
  for (ENetList* list : {&peer->sentReliableCommands, &peer->outgoingCommands}) {
    for (ENetListIterator i = enet_list_begin(list); i != enet_list_end(list); i = enet_list_next(i)) {
      auto* command = reinterpret_cast<ENetOutgoingCommand*>(i);
      if (command->roundTripTimeout > cap) command->roundTripTimeout = cap;
    }
  }
  // ENet looks for lost packets only once its next timeout has come, set from the oldest packet sent.
  if (!enet_list_empty(&peer->sentReliableCommands)) {
    const auto* oldest = reinterpret_cast<const ENetOutgoingCommand*>(enet_list_begin(&peer->sentReliableCommands));
    const enet_uint32 due = oldest->sentTime + oldest->roundTripTimeout;
    if (ENET_TIME_LESS(due, peer->nextTimeout)) peer->nextTimeout = due;
  }
}

// Whether a message sent to the peer is still unacknowledged (or unsent). Only commands that carry a
// packet count: ENet's own pings, sent every half second, would keep a lossy link busy for ever.
bool messagesInFlight(ENetPeer* peer) {
  for (ENetList* list : {&peer->sentReliableCommands, &peer->outgoingCommands}) {
    for (ENetListIterator i = enet_list_begin(list); i != enet_list_end(list); i = enet_list_next(i)) {
      if (reinterpret_cast<const ENetOutgoingCommand*>(i)->packet != nullptr) return true;
    }
  }
  return false;
}

size_t countMessagesInFlight(ENetPeer* peer) {
  size_t n = 0;
  for (ENetList* list : {&peer->sentReliableCommands, &peer->outgoingCommands}) {
    for (ENetListIterator i = enet_list_begin(list); i != enet_list_end(list); i = enet_list_next(i)) {
      if (reinterpret_cast<const ENetOutgoingCommand*>(i)->packet != nullptr) ++n;
    }
  }
  return n;
}

}  // namespace

struct Transport::Impl {
  ENetHost* host = nullptr;
  ENetPeer* peer = nullptr;  // the one peer, once connected (joiner: from the start, while connecting)
  bool connected = false;
  bool hadPeer = false;       // a host takes one player in its life: a later one is turned away
  enet_uint32 timeoutMs = 0;  // 0: ENet's own defaults
  bool spectatorSlot = false;
  ENetPeer* spectator = nullptr;  // the spectator, once connected; the slot is free again when it leaves
  LinkCounts peerCounts, spectatorCounts;
  // What closeSpectator() saw of everything else while it lingered: the player's packets must not be
  // lost for it. poll() hands them out first, in order.
  std::deque<ENetEvent> deferred;

  ~Impl() {
    for (ENetEvent& e : deferred) {
      if (e.type == ENET_EVENT_TYPE_RECEIVE) enet_packet_destroy(e.packet);
    }
    if (peer && connected) enet_peer_disconnect_now(peer, 0);
    if (spectator) enet_peer_disconnect_now(spectator, 0);
    if (host) enet_host_destroy(host);
  }

  void applyTimeout(ENetPeer* p) {
    if (p && timeoutMs) enet_peer_timeout(p, 0, timeoutMs, timeoutMs);
  }
  void applyTimeout() {
    applyTimeout(peer);
    applyTimeout(spectator);
  }

  void sendPacket(ENetPeer* to, LinkCounts& counts, const uint8_t* data, size_t size) {
    ENetPacket* packet = enet_packet_create(data, size, ENET_PACKET_FLAG_RELIABLE);
    if (!packet) throw TransportError("out of memory for a packet of " + std::to_string(size) + " bytes");
    if (enet_peer_send(to, 0, packet) < 0) {
      enet_packet_destroy(packet);
      throw TransportError("ENet refused a packet of " + std::to_string(size) + " bytes");
    }
    ++counts.messagesSent;
    counts.bytesSent += size;
    // Out now rather than at the next poll: the peer may be waiting for exactly this.
    enet_host_flush(host);
    capResends();
  }
  void sendPacket(const uint8_t* data, size_t size) {
    if (!peer || !connected) return;
    sendPacket(peer, peerCounts, data, size);
  }

  void capResends() {
    if (peer && connected) capResendTimeouts(peer);
    if (spectator) capResendTimeouts(spectator);
  }
};

Transport::Transport(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Transport::~Transport() = default;

std::unique_ptr<Transport> Transport::host(uint16_t port, bool spectatorSlot) {
  initializeEnet();
  ENetAddress address{};
  address.host = ENET_HOST_ANY;
  address.port = port;
  auto impl = std::make_unique<Impl>();
  impl->spectatorSlot = spectatorSlot;
  impl->host = enet_host_create(&address, spectatorSlot ? 2 : 1, 1, 0, 0);
  if (!impl->host) throw TransportError("cannot listen on UDP port " + std::to_string(port) + " (is it in use?)");
  limit(impl->host);
  return std::unique_ptr<Transport>(new Transport(std::move(impl)));
}

std::unique_ptr<Transport> Transport::join(const std::string& hostName, uint16_t port) {
  initializeEnet();
  ENetAddress address{};
  if (hostName.empty() || enet_address_set_host(&address, hostName.c_str()) != 0) {
    throw TransportError("cannot resolve the host name '" + hostName + "'");
  }
  address.port = port;
  auto impl = std::make_unique<Impl>();
  impl->host = enet_host_create(nullptr, 1, 1, 0, 0);
  if (!impl->host) throw TransportError("cannot open a UDP socket");
  limit(impl->host);
  impl->peer = enet_host_connect(impl->host, &address, 1, 0);
  if (!impl->peer) throw TransportError("ENet cannot start a connection to " + hostName + ":" + std::to_string(port));
  impl->hadPeer = true;
  return std::unique_ptr<Transport>(new Transport(std::move(impl)));
}

uint16_t Transport::localPort() const {
  ENetAddress address{};
  if (enet_socket_get_address(impl_->host->socket, &address) != 0) return 0;
  return address.port;
}

bool Transport::connected() const { return impl_->connected; }

void Transport::setPeerTimeout(double seconds) {
  impl_->timeoutMs = std::max<enet_uint32>(1, milliseconds(seconds));
  impl_->applyTimeout();
}

void Transport::send(const Message& message) {
  const std::vector<uint8_t> bytes = encode(message);
  impl_->sendPacket(bytes.data(), bytes.size());
}

void Transport::sendBytes(const std::vector<uint8_t>& bytes) { impl_->sendPacket(bytes.data(), bytes.size()); }

TransportEvent Transport::poll(double timeoutSeconds, const DecodeContext& context) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(std::max(0.0, timeoutSeconds));
  Impl& m = *impl_;
  TransportEvent out;
  for (;;) {
    const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
    ENetEvent event{};
    int got = 0;
    if (!m.deferred.empty()) {
      event = m.deferred.front();
      m.deferred.pop_front();
      got = 1;
    } else {
      got = enet_host_service(m.host, &event, milliseconds(left));
      if (got < 0) throw TransportError("the network failed while waiting for packets");
      m.capResends();
      if (got == 0) return out;
    }
    switch (event.type) {
      case ENET_EVENT_TYPE_CONNECT:
        if (m.peer == event.peer && !m.connected) {  // the joiner's attempt succeeded
          m.connected = true;
          out.kind = TransportEvent::Kind::Connected;
          return out;
        }
        if (!m.hadPeer) {  // the host's first peer: the player
          m.peer = event.peer;
          m.hadPeer = m.connected = true;
          m.applyTimeout(m.peer);
          out.kind = TransportEvent::Kind::Connected;
          return out;
        }
        // A spectator watches a game under way: only once the player is here, and one at a time.
        if (m.spectatorSlot && m.connected && !m.spectator) {
          m.spectator = event.peer;
          m.applyTimeout(m.spectator);
          out.kind = TransportEvent::Kind::Connected;
          out.spectator = true;
          return out;
        }
        enet_peer_disconnect_now(event.peer, 0);
        break;
      case ENET_EVENT_TYPE_RECEIVE: {
        const bool fromSpectator = m.spectator && event.peer == m.spectator;
        const bool ours = (m.connected && event.peer == m.peer) || fromSpectator;
        if (ours) {
          LinkCounts& counts = fromSpectator ? m.spectatorCounts : m.peerCounts;
          ++counts.messagesReceived;
          counts.bytesReceived += event.packet->dataLength;
          out.spectator = fromSpectator;
          Decoded decoded = decode(event.packet->data, event.packet->dataLength, context);
          if (decoded.ok()) {
            out.kind = TransportEvent::Kind::Received;
            out.message = std::move(decoded.message);
          } else {
            out.kind = TransportEvent::Kind::Garbage;
            out.error = std::move(decoded.error);
          }
        }
        enet_packet_destroy(event.packet);
        if (ours) return out;
        break;
      }
      case ENET_EVENT_TYPE_DISCONNECT:
        if (m.spectator && event.peer == m.spectator) {
          m.spectator = nullptr;
          out.kind = TransportEvent::Kind::Disconnected;
          out.spectator = true;
          return out;
        }
        if (event.peer == m.peer) {
          m.peer = nullptr;
          m.connected = false;
          out.kind = TransportEvent::Kind::Disconnected;
          return out;
        }
        break;
      case ENET_EVENT_TYPE_NONE:
        break;
    }
    if (Clock::now() >= deadline) return out;
  }
}

void Transport::close(double lingerSeconds) {
  using Clock = std::chrono::steady_clock;
  Impl& m = *impl_;
  if (!m.peer) return;
  if (m.connected) {
    // Linger until the peer has acknowledged every message sent (the last Bye or Refuse), then leave at
    // once. Not ENet's polite disconnect: a side in it stops acknowledging, so when both sides close
    // together each can wait for the other until the linger runs out.
    const auto deadline = Clock::now() + std::chrono::duration<double>(std::max(0.0, lingerSeconds));
    while (messagesInFlight(m.peer)) {
      const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
      if (left <= 0) break;
      ENetEvent event{};
      const int got = enet_host_service(m.host, &event, milliseconds(std::min(left, 0.01)));
      if (got < 0) break;
      m.capResends();
      if (got > 0 && event.type == ENET_EVENT_TYPE_RECEIVE) enet_packet_destroy(event.packet);
      if (got > 0 && event.type == ENET_EVENT_TYPE_DISCONNECT && m.spectator && event.peer == m.spectator) {
        m.spectator = nullptr;
      }
      if (got > 0 && event.type == ENET_EVENT_TYPE_DISCONNECT && event.peer == m.peer) {
        m.peer = nullptr;
        m.connected = false;
        return;
      }
    }
    enet_peer_disconnect_now(m.peer, 0);
  } else {
    enet_peer_reset(m.peer);
  }
  m.peer = nullptr;
  m.connected = false;
}

void Transport::acceptAnotherPeer() {
  if (!impl_->connected) impl_->hadPeer = false;
}

bool Transport::spectatorConnected() const { return impl_->spectator != nullptr; }

void Transport::sendToSpectator(const Message& message) {
  if (!impl_->spectator) return;
  const std::vector<uint8_t> bytes = encode(message);
  impl_->sendPacket(impl_->spectator, impl_->spectatorCounts, bytes.data(), bytes.size());
}

size_t Transport::spectatorBacklog() const {
  return impl_->spectator ? countMessagesInFlight(impl_->spectator) : 0;
}

void Transport::closeSpectator(double lingerSeconds) {
  using Clock = std::chrono::steady_clock;
  Impl& m = *impl_;
  if (!m.spectator) return;
  // As close(): until the spectator has everything sent, then at once. The player's packets that come
  // meanwhile are kept for poll(): the game goes on, and every one of them is awaited.
  const auto deadline = Clock::now() + std::chrono::duration<double>(std::max(0.0, lingerSeconds));
  while (m.spectator && messagesInFlight(m.spectator)) {
    const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
    if (left <= 0) break;
    ENetEvent event{};
    const int got = enet_host_service(m.host, &event, milliseconds(std::min(left, 0.01)));
    if (got < 0) break;
    m.capResends();
    if (got == 0) continue;
    if (event.peer == m.spectator) {
      // The spectator's last words are not waited for; its leaving ends the linger.
      if (event.type == ENET_EVENT_TYPE_RECEIVE) enet_packet_destroy(event.packet);
      if (event.type == ENET_EVENT_TYPE_DISCONNECT) m.spectator = nullptr;
    } else {
      m.deferred.push_back(event);  // the player's, for poll()
    }
  }
  if (m.spectator) enet_peer_disconnect_now(m.spectator, 0);
  m.spectator = nullptr;
}

const LinkCounts& Transport::peerCounts() const { return impl_->peerCounts; }
const LinkCounts& Transport::spectatorCounts() const { return impl_->spectatorCounts; }

SocketCounts Transport::socketCounts() const {
  const ENetHost* h = impl_->host;
  return {h->totalSentPackets, h->totalSentData, h->totalReceivedPackets, h->totalReceivedData};
}

}  // namespace rts::net
