// The memory trend of a long-running process from samples of its resident
// set size: start, maximum, end, and the growth per hour as the least
// squares slope over the samples after a warm-up (allocator pools, first
// solver problems and caches fill in the first minutes and then stay).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace evade::soak {

struct RssSample {
  double t_s = 0.0;    // since the soak started
  int64_t pid = 0;     // the sampled process
  double rss_kib = 0;  // VmRSS
  double load1 = 0;    // the host's 1-minute load average at the sample
};

struct RssTrend {
  int64_t pid = 0;
  int samples = 0;
  double span_s = 0.0;  // first to last sample
  double start_mib = 0.0, max_mib = 0.0, end_mib = 0.0;
  int fitted = 0;                          // samples at or after the warm-up
  std::optional<double> growth_mib_per_h;  // none with fewer than 2 fitted samples
};

// Parses the sampler's file: one "t_s pid rss_kib load1" line per sample,
// blank lines and lines starting with '#' ignored. Throws
// std::runtime_error naming the line for anything else.
std::vector<RssSample> parse_rss_samples(const std::string& text);

// Least squares slope of y over x (units of y per unit of x); none with
// fewer than 2 points or all x equal.
std::optional<double> ls_slope(const std::vector<double>& x, const std::vector<double>& y);

// One trend per process, in the order the processes first appear; the
// warm-up counts from each process's first sample.
std::vector<RssTrend> rss_trends(const std::vector<RssSample>& samples, double warmup_s);

}  // namespace evade::soak
