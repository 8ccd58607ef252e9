// rattle-bench: the row a run prints, with one set of columns for every scene (so that the rows of a
// matrix share one CSV header), and the small number helpers the runs share.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace rattle_bench {

class Row {
 public:
  /// Every column, in order, empty.
  Row();
  /// Sets a column. Throws std::logic_error for a name that is not a column (a bug, not a user error).
  void set(const std::string& column, std::string value);
  /// `csv`: a header line and the row; else one named value a line, then `reference` (how the exact
  /// reference was found) when it is not empty.
  void print(bool csv, const std::string& reference) const;

 private:
  std::vector<std::pair<std::string, std::string>> cells_;
};

/// v printed with `format`; empty for NaN (an empty CSV cell).
std::string num(double v, const char* format = "%.6g");

/// The p-th quantile (0 < p <= 1) by nearest rank: the smallest value with at least p of the values at or
/// below it (p = 1: the largest); NaN for an empty vector.
double percentile(std::vector<double> v, double p);

/// The median; NaN for an empty vector.
double median(std::vector<double> v);

/// A progress line on stderr for long runs: nothing in the first two seconds, then at most one update a
/// second (rewritten in place on a terminal, one line every ten seconds otherwise).
class Progress {
 public:
  Progress(bool enabled, std::string label);
  void update(const std::string& what, long long done, long long total);
  void finish();

 private:
  bool enabled_, tty_;
  std::string label_;
  double start_;
  double last_ = 0;
  bool shown_ = false;
};

}  // namespace rattle_bench
