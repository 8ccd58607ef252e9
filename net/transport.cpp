#include "net/transport.h"

#include <enet/enet.h>
#include <enet/time.h>

#include <algorithm>
#include <chrono>
#include <cmath>

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

}  // namespace

struct Transport::Impl {
  ENetHost* host = nullptr;
  ENetPeer* peer = nullptr;  // the one peer, once connected (joiner: from the start, while connecting)
  bool connected = false;
  bool hadPeer = false;       // a host takes one peer in its life: a later one is turned away
  enet_uint32 timeoutMs = 0;  // 0: ENet's own defaults

  ~Impl() {
    if (peer && connected) enet_peer_disconnect_now(peer, 0);
    if (host) enet_host_destroy(host);
  }

  void applyTimeout() {
    if (peer && timeoutMs) enet_peer_timeout(peer, 0, timeoutMs, timeoutMs);
  }

  void sendPacket(const uint8_t* data, size_t size) {
    if (!peer || !connected) return;
    ENetPacket* packet = enet_packet_create(data, size, ENET_PACKET_FLAG_RELIABLE);
    if (!packet) throw TransportError("out of memory for a packet of " + std::to_string(size) + " bytes");
    if (enet_peer_send(peer, 0, packet) < 0) {
      enet_packet_destroy(packet);
      throw TransportError("ENet refused a packet of " + std::to_string(size) + " bytes");
    }
    // Out now rather than at the next poll: the peer may be waiting for exactly this.
    enet_host_flush(host);
    capResends();
  }

  void capResends() {
    if (peer && connected) capResendTimeouts(peer);
  }
};

Transport::Transport(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Transport::~Transport() = default;

std::unique_ptr<Transport> Transport::host(uint16_t port) {
  initializeEnet();
  ENetAddress address{};
  address.host = ENET_HOST_ANY;
  address.port = port;
  auto impl = std::make_unique<Impl>();
  impl->host = enet_host_create(&address, 1, 1, 0, 0);
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
    const int got = enet_host_service(m.host, &event, milliseconds(left));
    if (got < 0) throw TransportError("the network failed while waiting for packets");
    m.capResends();
    if (got == 0) return out;
    switch (event.type) {
      case ENET_EVENT_TYPE_CONNECT:
        if (m.peer == event.peer && !m.connected) {  // the joiner's attempt succeeded
          m.connected = true;
          out.kind = TransportEvent::Kind::Connected;
          return out;
        }
        if (!m.hadPeer) {  // the host's first and only peer
          m.peer = event.peer;
          m.hadPeer = m.connected = true;
          m.applyTimeout();
          out.kind = TransportEvent::Kind::Connected;
          return out;
        }
        enet_peer_disconnect_now(event.peer, 0);
        break;
      case ENET_EVENT_TYPE_RECEIVE: {
        const bool ours = m.connected && event.peer == m.peer;
        if (ours) {
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

}  // namespace rts::net
