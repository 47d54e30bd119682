// The health board: one table row per process heard on HEALTH, built from
// the newest heartbeat of each and the current time. No socket, no clock:
// the caller hands in the heartbeats with their receive times and `now`.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "config/config.h"
#include "config/fields.h"
#include "evade/health_t.hpp"

namespace evade::health {

struct HealthBoardParams {
  double stale_after_s = 2.5;     // a heartbeat older than this is stale (processes beat once a second)
  double once_listen_s = 3.0;     // --once listens this long before it judges
  double refresh_period_s = 1.0;  // s between redraws
  double wait_timeout_s = 10.0;   // --wait-received gives up after this long

  template <class V>
  void fields(V& v) {
    v.field("stale_after_s", stale_after_s, config::between(0.1, 3600.0));
    v.field("once_listen_s", once_listen_s, config::between(0.1, 60.0));
    v.field("refresh_period_s", refresh_period_s, config::between(0.05, 60.0));
    v.field("wait_timeout_s", wait_timeout_s, config::between(0.1, 600.0));
  }
  // Reads the `health_board:` section (closed); errors name file, line and key.
  static HealthBoardParams from_config(const config::Node& section);
};

// The newest heartbeat of one process and the bus time it arrived.
struct Heartbeat {
  evade::health_t msg;
  int64_t received_utime = 0;
};

class HealthBoard {
 public:
  // Keeps the newest heartbeat per process name.
  void add(const evade::health_t& msg, int64_t received_utime);
  const std::map<std::string, Heartbeat>& processes() const { return latest_; }

 private:
  std::map<std::string, Heartbeat> latest_;
};

struct Verdict {
  std::vector<std::string> stale;    // heard, but the last heartbeat is older than stale_after_s
  std::vector<std::string> missing;  // expected, never heard
  bool ok() const { return stale.empty() && missing.empty(); }
};

Verdict judge(const HealthBoard& board, const std::vector<std::string>& expected, int64_t now_utime,
              const HealthBoardParams& params);

// An input that a process must have received: "PROCESS:CHANNEL" (for
// example "planner:ROUTE"). Parses one; false (and `why`) when malformed.
struct InputWanted {
  std::string process, channel;
};
bool parse_input_wanted(const std::string& text, InputWanted* out, std::string* why);

// Of `wanted`, those whose process has not been heard or whose newest
// heartbeat counts no message received on that input, as "PROCESS:CHANNEL".
// Empty: every one has arrived (a launcher may start what depends on it).
std::vector<std::string> inputs_not_received(const HealthBoard& board, const std::vector<InputWanted>& wanted);

// The table, lines of at most kTableWidth visible characters (ANSI colour
// codes do not count): a header, then per process one row
//   name, heartbeat age (s), output rate (Hz), handler latency mean and max
//   (ms), its oldest input and that input's age (s)
// and, when it has any, an indented line (wrapped) of its non-zero counters.
// Stale rows are red when `colour`; expected processes never heard get a
// "missing" row.
inline constexpr int kTableWidth = 80;
std::vector<std::string> render_table(const HealthBoard& board, const std::vector<std::string>& expected,
                                      int64_t now_utime, const HealthBoardParams& params, bool colour);

}  // namespace evade::health
