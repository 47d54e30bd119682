#include "soak/rss_trend.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "soak/report_text.h"

namespace evade::soak {

std::vector<RssSample> parse_rss_samples(const std::string& text) {
  std::vector<RssSample> out;
  for_each_line(text, true, [&](const std::string& line, int n) {
    std::istringstream ls(line);
    RssSample s;
    std::string extra;
    if (!(ls >> s.t_s >> s.pid >> s.rss_kib >> s.load1) || (ls >> extra) || !std::isfinite(s.t_s) || s.rss_kib < 0 ||
        !std::isfinite(s.rss_kib))
      throw std::runtime_error("line " + std::to_string(n) + ": want 't_s pid rss_kib load1', got '" + line + "'");
    out.push_back(s);
  });
  return out;
}

std::optional<double> ls_slope(const std::vector<double>& x, const std::vector<double>& y) {
  const size_t n = std::min(x.size(), y.size());
  if (n < 2) return std::nullopt;
  double mx = 0, my = 0;
  for (size_t i = 0; i < n; ++i) mx += x[i], my += y[i];
  mx /= n, my /= n;
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < n; ++i) sxx += (x[i] - mx) * (x[i] - mx), sxy += (x[i] - mx) * (y[i] - my);
  if (sxx <= 0) return std::nullopt;
  return sxy / sxx;
}

std::vector<RssTrend> rss_trends(const std::vector<RssSample>& samples, double warmup_s) {
  std::vector<int64_t> pids;
  for (const auto& s : samples)
    if (std::find(pids.begin(), pids.end(), s.pid) == pids.end()) pids.push_back(s.pid);
  std::vector<RssTrend> out;
  for (int64_t pid : pids) {
    RssTrend t;
    t.pid = pid;
    double t0 = 0, t_last = 0;
    std::vector<double> xs, ys;
    for (const auto& s : samples) {
      if (s.pid != pid) continue;
      const double mib = s.rss_kib / 1024.0;
      if (t.samples++ == 0) t0 = s.t_s, t.start_mib = mib, t.max_mib = mib;
      t.max_mib = std::max(t.max_mib, mib);
      t.end_mib = mib;
      t_last = s.t_s;
      if (s.t_s - t0 >= warmup_s) xs.push_back(s.t_s / 3600.0), ys.push_back(mib);
    }
    t.span_s = t_last - t0;
    t.fitted = static_cast<int>(xs.size());
    t.growth_mib_per_h = ls_slope(xs, ys);
    out.push_back(t);
  }
  return out;
}

}  // namespace evade::soak
