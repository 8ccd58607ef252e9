// rattle-relay: the tests' faulty network (net/faulty_relay.h) as a program, to watch two rattle-demo
// processes play through it by hand:
//   rattle-demo --host 47800 --no-render ...
//   rattle-relay --listen 47801 --to 127.0.0.1:47800
//   rattle-demo --join 127.0.0.1:47801 --no-render --input-delay 15 ...
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <thread>

#include "net/faulty_relay.h"

namespace {

volatile std::sig_atomic_t interrupted = 0;
void onSignal(int) { interrupted = 1; }

const char* const kHelp =
    "usage: rattle-relay --to HOST:PORT [--listen PORT] [--seed N] [--drop P] [--duplicate P]\n"
    "                    [--reorder P] [--delay MIN-MAX] [--seconds S]\n"
    "\n"
    "Forwards UDP datagrams between one joiner and a host (a rattle-demo --host), and on the way\n"
    "drops, duplicates, holds back and delays them, as a bad network would. Stop it with Ctrl-C.\n"
    "\n"
    "  --to HOST:PORT   the host to forward to (required)\n"
    "  --listen PORT    the UDP port the joiner connects to (default 0: a free one, printed)\n"
    "  --seed N         the faults' seed, 0 to 2^53: the n-th datagram each way meets the same fate\n"
    "                   (default 26)\n"
    "  --drop P         the probability a datagram is lost (default 0.10)\n"
    "  --duplicate P    the probability it is sent twice (default 0.05)\n"
    "  --reorder P      the probability it is held back behind the next one (default 0.05)\n"
    "  --delay MIN-MAX  every datagram waits MIN to MAX milliseconds (each 0 to 10000), uniformly\n"
    "                   (default 50-200)\n"
    "  --seconds S      stop after S seconds, 0.1 to 86400 (default: when interrupted)\n"
    "\n"
    "exit status: 0 stopped, 1 the port or host did not work, 2 bad options\n";

[[noreturn]] void bad(const std::string& what) {
  std::fprintf(stderr, "rattle-relay: %s (see --help)\n", what.c_str());
  std::exit(2);
}

/// `range` says what is expected, for the error: "a probability from 0 to 1". `quote`: the error
/// quotes `text` after the option (false: `option` already holds what to quote).
double number(const std::string& option, const std::string& text, double lo, double hi, const char* range,
              bool quote = true) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(v >= lo && v <= hi))
    bad(option + (quote ? " " + text : std::string()) + ": expected " + range);
  return v;
}

/// `shown` is what the error quotes: the option's whole value.
uint16_t port(const std::string& option, const std::string& shown, const std::string& text, int lo) {
  const std::string expected = lo == 0 ? "expected a port from 0 to 65535" : "expected a port from 1 to 65535";
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < lo || v > 65535) bad(option + " " + shown + ": " + expected);
  return uint16_t(v);
}

}  // namespace

int main(int argc, char** argv) {
  rts::net::FaultModel model;
  uint16_t listen = 0, hostPort = 0;
  std::string host;
  double seconds = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::fputs(kHelp, stdout);
      return 0;
    }
    if (i + 1 >= argc) {
      const bool known = a == "--to" || a == "--listen" || a == "--seed" || a == "--drop" || a == "--duplicate" ||
                         a == "--reorder" || a == "--delay" || a == "--seconds";
      bad(a + (known ? ": a value is missing" : ": unknown option"));
    }
    const std::string v = argv[++i];
    if (a == "--to") {
      const size_t colon = v.rfind(':');
      if (colon == std::string::npos || colon == 0) bad("--to " + v + ": expected HOST:PORT");
      host = v.substr(0, colon);
      hostPort = port("--to", v, v.substr(colon + 1), 1);
    } else if (a == "--listen") {
      listen = port(a, v, v, 0);
    } else if (a == "--seed") {
      model.seed = uint64_t(number(a, v, 0, 9007199254740992.0, "a whole number from 0 to 2^53"));
      if (double(model.seed) != std::strtod(v.c_str(), nullptr))
        bad(a + " " + v + ": expected a whole number from 0 to 2^53");
    } else if (a == "--drop") {
      model.drop = number(a, v, 0, 1, "a probability from 0 to 1");
    } else if (a == "--duplicate") {
      model.duplicate = number(a, v, 0, 1, "a probability from 0 to 1");
    } else if (a == "--reorder") {
      model.reorder = number(a, v, 0, 1, "a probability from 0 to 1");
    } else if (a == "--delay") {
      const size_t dash = v.find('-');
      if (dash == std::string::npos) bad("--delay " + v + ": expected MIN-MAX in milliseconds, e.g. 50-200");
      // The error quotes the whole value (a "-5-10" has an empty MIN).
      const char* ms = "MIN-MAX, each milliseconds from 0 to 10000";
      model.minDelaySeconds = number(a + " " + v, v.substr(0, dash), 0, 10000, ms, false) / 1000;
      model.maxDelaySeconds = number(a + " " + v, v.substr(dash + 1), 0, 10000, ms, false) / 1000;
      if (model.minDelaySeconds > model.maxDelaySeconds) bad("--delay " + v + ": MIN is above MAX");
    } else if (a == "--seconds") {
      seconds = number(a, v, 0.1, 86400, "seconds from 0.1 to 86400");
    } else {
      bad(a + ": unknown option");
    }
  }
  if (host.empty()) bad("--to HOST:PORT is required");
  try {
    rts::net::FaultyRelay relay(listen, host, hostPort, model);
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    relay.start();
    std::fprintf(stderr,
                 "rattle-relay: relaying UDP port %u to %s:%u: %.0f%% dropped, %.0f%% duplicated, %.0f%% held back, "
                 "%.0f-%.0f ms of delay, seed %llu\n",
                 relay.port(), host.c_str(), hostPort, model.drop * 100, model.duplicate * 100, model.reorder * 100,
                 model.minDelaySeconds * 1000, model.maxDelaySeconds * 1000,
                 static_cast<unsigned long long>(model.seed));
    const auto start = std::chrono::steady_clock::now();
    while (
        !interrupted &&
        (seconds == 0 || std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < seconds)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    relay.stop();
    for (const auto& [way, c] :
         {std::pair{"to the host", relay.towardsHost()}, {"to the joiner", relay.towardsJoiner()}}) {
      std::fprintf(stderr,
                   "rattle-relay: %s: %llu datagrams in, %llu dropped, %llu duplicated, %llu held back, %llu out\n",
                   way, static_cast<unsigned long long>(c.received), static_cast<unsigned long long>(c.dropped),
                   static_cast<unsigned long long>(c.duplicated), static_cast<unsigned long long>(c.heldBack),
                   static_cast<unsigned long long>(c.sent));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rattle-%s\n", e.what());
    return 1;
  }
  return 0;
}
