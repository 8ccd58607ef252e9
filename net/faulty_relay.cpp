#include "net/faulty_relay.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <mutex>
#include <optional>
#include <queue>
#include <stdexcept>
#include <thread>
#include <vector>

namespace rts::net {
namespace {

using Clock = std::chrono::steady_clock;

// SplitMix64: tiny, and the same numbers on every platform and standard library (std's distributions
// are not), so a seed means the same faults everywhere.
class Generator {
 public:
  explicit Generator(uint64_t seed) : state_(seed) {}
  /// Uniform in [0, 1), from the top 53 bits.
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }

 private:
  uint64_t next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  uint64_t state_;
};

enum Way { kTowardsHost = 0, kTowardsJoiner = 1 };

struct Datagram {
  Clock::time_point due;
  uint64_t order = 0;  // ties go out in the order they were scheduled
  Way way = kTowardsHost;
  std::vector<uint8_t> bytes;
  bool operator>(const Datagram& o) const { return due != o.due ? due > o.due : order > o.order; }
};

void checkModel(const FaultModel& m) {
  for (const auto& [name, p] : {std::pair{"drop", m.drop}, {"duplicate", m.duplicate}, {"reorder", m.reorder}}) {
    if (!(p >= 0 && p <= 1))
      throw std::runtime_error(std::string("relay: ") + name + " probability " + std::to_string(p) +
                               " is not between 0 and 1");
  }
  if (!(m.minDelaySeconds >= 0 && m.minDelaySeconds <= m.maxDelaySeconds && m.maxDelaySeconds <= 10)) {
    throw std::runtime_error("relay: delays " + std::to_string(m.minDelaySeconds) + " to " +
                             std::to_string(m.maxDelaySeconds) + " s: expected 0 <= min <= max <= 10");
  }
}

int udpSocket() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) throw std::runtime_error(std::string("relay: cannot open a UDP socket (") + std::strerror(errno) + ")");
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
  return fd;
}

}  // namespace

struct FaultyRelay::Impl {
  FaultModel model;
  int front = -1;  // the joiner's side: bound to the relay's port
  int back = -1;   // the host's side: connected to the host
  sockaddr_in joiner{};
  bool haveJoiner = false;

  // One generator each way, so that one way's traffic does not shift the other's faults.
  Generator generators[2];
  struct Held {
    std::optional<Datagram> datagram;
    Clock::time_point latest;  // released then even when nothing comes after it
  } held[2];
  std::priority_queue<Datagram, std::vector<Datagram>, std::greater<>> pending;
  uint64_t scheduled = 0;

  mutable std::mutex countsMutex;
  RelayCounts counts[2];

  std::thread thread;
  std::atomic<bool> stopping{false};

  explicit Impl(const FaultModel& m)
      : model(m), generators{Generator(m.seed), Generator(m.seed ^ 0x5851f42d4c957f2dull)} {}
  ~Impl() {
    if (front >= 0) ::close(front);
    if (back >= 0) ::close(back);
  }

  void count(Way way, uint64_t RelayCounts::*field, uint64_t n = 1) {
    std::lock_guard<std::mutex> lock(countsMutex);
    counts[way].*field += n;
  }

  void schedule(Way way, Clock::time_point due, std::vector<uint8_t> bytes) {
    pending.push(Datagram{due, scheduled++, way, std::move(bytes)});
  }

  Clock::duration delay(double u) const {
    return std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(model.minDelaySeconds + u * (model.maxDelaySeconds - model.minDelaySeconds)));
  }

  // One datagram's fate. Five draws whatever happens to it, so the n-th datagram's fate depends on the
  // seed and n alone.
  void arrive(Way way, std::vector<uint8_t> bytes, Clock::time_point now) {
    Generator& g = generators[way];
    const double drop = g.uniform(), duplicate = g.uniform(), reorder = g.uniform(), wait = g.uniform(),
                 copyWait = g.uniform();
    count(way, &RelayCounts::received);
    if (drop < model.drop) {
      count(way, &RelayCounts::dropped);
      return;
    }
    const Clock::time_point due = now + delay(wait);
    if (duplicate < model.duplicate) {
      count(way, &RelayCounts::duplicated);
      schedule(way, now + delay(copyWait), bytes);
    }
    Held& h = held[way];
    if (reorder < model.reorder && !h.datagram) {
      count(way, &RelayCounts::heldBack);
      h.datagram = Datagram{due, 0, way, std::move(bytes)};
      h.latest = due + delay(1.0);
      return;
    }
    schedule(way, due, std::move(bytes));
    if (h.datagram) {
      // Behind this one: a millisecond after it, whenever it was due itself.
      schedule(way, std::max(due, h.datagram->due) + std::chrono::milliseconds(1), std::move(h.datagram->bytes));
      h.datagram.reset();
    }
  }

  void release(Clock::time_point now) {
    for (Held& h : held) {
      if (h.datagram && now >= h.latest) {
        schedule(h.datagram->way, now, std::move(h.datagram->bytes));
        h.datagram.reset();
      }
    }
    while (!pending.empty() && pending.top().due <= now) {
      const Datagram& d = pending.top();
      // A failed send is one more lost datagram, which is what this relay is for; ENet resends.
      if (d.way == kTowardsHost) {
        ::send(back, d.bytes.data(), d.bytes.size(), 0);
        count(kTowardsHost, &RelayCounts::sent);
      } else if (haveJoiner) {
        ::sendto(front, d.bytes.data(), d.bytes.size(), 0, reinterpret_cast<const sockaddr*>(&joiner), sizeof joiner);
        count(kTowardsJoiner, &RelayCounts::sent);
      }
      pending.pop();
    }
  }

  void receive(Clock::time_point now) {
    std::vector<uint8_t> buffer(65536);
    for (;;) {
      sockaddr_in from{};
      socklen_t length = sizeof from;
      const ssize_t n = ::recvfrom(front, buffer.data(), buffer.size(), 0, reinterpret_cast<sockaddr*>(&from), &length);
      if (n < 0) break;
      if (!haveJoiner) {
        joiner = from;
        haveJoiner = true;
      } else if (from.sin_addr.s_addr != joiner.sin_addr.s_addr || from.sin_port != joiner.sin_port) {
        count(kTowardsHost, &RelayCounts::strangers);
        continue;
      }
      arrive(kTowardsHost, {buffer.begin(), buffer.begin() + n}, now);
    }
    for (;;) {
      // Connected: only the host's datagrams come here. An ICMP error (the host not there yet) reads as
      // an error and is skipped.
      const ssize_t n = ::recv(back, buffer.data(), buffer.size(), 0);
      if (n < 0 && errno == ECONNREFUSED) continue;
      if (n < 0) break;
      arrive(kTowardsJoiner, {buffer.begin(), buffer.begin() + n}, now);
    }
  }

  void run() {
    while (!stopping.load()) {
      const Clock::time_point now = Clock::now();
      release(now);
      // Wake for the next due datagram, and at least every 5 ms to notice stop().
      auto wait = std::chrono::milliseconds(5);
      if (!pending.empty()) {
        wait = std::min(wait, std::chrono::ceil<std::chrono::milliseconds>(pending.top().due - now));
      }
      pollfd fds[2] = {{front, POLLIN, 0}, {back, POLLIN, 0}};
      ::poll(fds, 2, int(std::max<int64_t>(0, wait.count())));
      receive(Clock::now());
    }
  }
};

FaultyRelay::FaultyRelay(uint16_t listenPort, const std::string& hostName, uint16_t hostPort, const FaultModel& model)
    : impl_(std::make_unique<Impl>(model)) {
  checkModel(model);
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  if (hostName.empty() || ::getaddrinfo(hostName.c_str(), nullptr, &hints, &found) != 0 || !found) {
    throw std::runtime_error("relay: cannot resolve the host name '" + hostName + "'");
  }
  sockaddr_in host = *reinterpret_cast<const sockaddr_in*>(found->ai_addr);
  ::freeaddrinfo(found);
  host.sin_port = htons(hostPort);

  impl_->front = udpSocket();
  sockaddr_in any{};
  any.sin_family = AF_INET;
  any.sin_addr.s_addr = htonl(INADDR_ANY);
  any.sin_port = htons(listenPort);
  if (::bind(impl_->front, reinterpret_cast<const sockaddr*>(&any), sizeof any) != 0) {
    throw std::runtime_error("relay: cannot listen on UDP port " + std::to_string(listenPort) + " (" +
                             std::strerror(errno) + ")");
  }
  impl_->back = udpSocket();
  if (::connect(impl_->back, reinterpret_cast<const sockaddr*>(&host), sizeof host) != 0) {
    throw std::runtime_error("relay: cannot reach " + hostName + ":" + std::to_string(hostPort) + " (" +
                             std::strerror(errno) + ")");
  }
}

FaultyRelay::~FaultyRelay() { stop(); }

uint16_t FaultyRelay::port() const {
  sockaddr_in address{};
  socklen_t length = sizeof address;
  if (::getsockname(impl_->front, reinterpret_cast<sockaddr*>(&address), &length) != 0) return 0;
  return ntohs(address.sin_port);
}

void FaultyRelay::start() {
  if (impl_->thread.joinable()) return;
  impl_->stopping = false;
  impl_->thread = std::thread([this] { impl_->run(); });
}

void FaultyRelay::stop() {
  impl_->stopping = true;
  if (impl_->thread.joinable()) impl_->thread.join();
}

RelayCounts FaultyRelay::towardsHost() const {
  std::lock_guard<std::mutex> lock(impl_->countsMutex);
  return impl_->counts[kTowardsHost];
}

RelayCounts FaultyRelay::towardsJoiner() const {
  std::lock_guard<std::mutex> lock(impl_->countsMutex);
  return impl_->counts[kTowardsJoiner];
}

}  // namespace rts::net
