// rattle-bench: the row every run prints (see row.h).
#include "row.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace rattle_bench {

namespace {

// The columns, in order. bench/README.md says what each one means, per scene.
const char* const kColumns[] = {
    "scene", "engine", "n", "dt", "seconds", "ms_per_step", "p99_ms_per_step", "worst_ms_per_step",
    "ms_per_simulated_second", "collisions_per_s",
    "energy_drift", "max_overlap", "mean_overlap", "tunnelled", "sensor_missed", "collision_count_error",
    // Beyond the columns: what the row was run with, and the raw counts.
    "seed", "packing", "speed", "steps", "warm_up_s", "collisions", "timed_collisions", "reference_collisions",
    "sensor_visits", "reference_sensor_visits", "wall_ms_per_step", "setup_s",
    // The arena scene's game counts (empty for the other scenes).
    "shots", "shots_out_of_range", "reference_shots", "reference_shots_out_of_range", "crossings",
    "reference_crossings",
    // The crowd scene's goal (empty for the other scenes), sleeping bodies at the end (empty when the engine
    // does not say), and whether --time-limit stopped the run (empty without a limit).
    "reached_goal", "asleep", "stopped_at_time_limit",
    "notes"};

std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

double monotonicSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

Row::Row() {
  for (const char* c : kColumns) cells_.emplace_back(c, "");
}

void Row::set(const std::string& column, std::string value) {
  for (auto& [name, v] : cells_)
    if (name == column) {
      v = std::move(value);
      return;
    }
  throw std::logic_error("rattle-bench: no column named " + column);
}

void Row::print(bool csv, const std::string& reference) const {
  if (csv) {
    std::string header, row;
    for (size_t i = 0; i < cells_.size(); ++i) {
      header += (i ? "," : "") + cells_[i].first;
      row += (i ? "," : "") + (cells_[i].first == "notes" ? quoted(cells_[i].second) : cells_[i].second);
    }
    std::printf("%s\n%s\n", header.c_str(), row.c_str());
    return;
  }
  for (const auto& [name, v] : cells_) std::printf("%-28s %s\n", name.c_str(), v.empty() ? "-" : v.c_str());
  if (!reference.empty()) std::printf("%-28s %s\n", "reference", reference.c_str());
}

std::string num(double v, const char* format) {
  if (std::isnan(v)) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  // Nearest rank: the smallest value with at least p of the values at or below it.
  size_t rank = static_cast<size_t>(std::ceil(p * static_cast<double>(v.size())));
  rank = std::clamp<size_t>(rank, 1, v.size());
  std::nth_element(v.begin(), v.begin() + static_cast<long>(rank - 1), v.end());
  return v[rank - 1];
}

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(mid), v.end());
  if (v.size() % 2 == 1) return v[mid];
  const double upper = v[mid];
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + static_cast<long>(mid)));
}

Progress::Progress(bool enabled, std::string label)
    : enabled_(enabled), tty_(isatty(2) != 0), label_(std::move(label)), start_(monotonicSeconds()) {}

void Progress::update(const std::string& what, long long done, long long total) {
  if (!enabled_) return;
  const double t = monotonicSeconds() - start_;
  if (t < 2.0 || t - last_ < (tty_ ? 1.0 : 10.0)) return;
  last_ = t;
  std::fprintf(stderr, "%srattle-bench %s: %s %lld/%lld (%.0f%%), %.0f s%s", tty_ ? "\r" : "", label_.c_str(),
               what.c_str(), done, total, 100.0 * static_cast<double>(done) / static_cast<double>(total), t,
               tty_ ? "   " : "\n");
  shown_ = true;
}

void Progress::finish() {
  if (shown_ && tty_) std::fprintf(stderr, "\n");
}

}  // namespace rattle_bench
