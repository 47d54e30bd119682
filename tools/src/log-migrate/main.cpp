// log-migrate: carries a log across a change of lcmtypes that only
// appended fields, so that golden logs need not be recorded again.
//
//   log-migrate MIGRATION IN.lcmlog OUT.lcmlog [--force]
//
// odometry-epoch (issue 20): ODOMETRY encoded before odometry_t gained
// `int64_t epoch` (fingerprint, utime, x, y, yaw, v, omega: 56 bytes) is
// re-encoded with the current type and epoch 0 (one frame throughout, as
// the recording was).
// sim-truth-returns (issue 23): SIM_TRUTH encoded before sim_truth_t gained
// `int32_t lidar_returns[num_obstacles]` gets the current fingerprint and
// -1 (unknown) for every obstacle.
// Every other event is copied as it is. OUT may be IN only with --force
// (it is written to a temporary file first).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstring>
#include <filesystem>

#include "bus/core.h"
#include "bus/log.h"
#include "evade/odometry_t.hpp"
#include "evade/sim_truth_t.hpp"

namespace {

int64_t be64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return static_cast<int64_t>(v);
}
double be_double(const uint8_t* p) {
  const int64_t bits = be64(p);
  double d;
  std::memcpy(&d, &bits, sizeof d);
  return d;
}

int32_t be32(const uint8_t* p) { return static_cast<int32_t>((uint32_t(p[0]) << 24) | (p[1] << 16) | (p[2] << 8) | p[3]); }

enum class Outcome { kMigrated, kCurrent, kForeign };

// One migration: the channel it applies to and how one event is carried over.
struct Migration {
  const char* name;
  const char* channel;
  Outcome (*apply)(std::vector<uint8_t>* data);
};

constexpr size_t kOldOdometrySize = 8 + 8 + 5 * 8;

Outcome odometry_epoch(std::vector<uint8_t>* data) {
  evade::odometry_t m;
  if (evade::bus::decode(data->data(), data->size(), &m)) return Outcome::kCurrent;
  if (data->size() != kOldOdometrySize) return Outcome::kForeign;
  const uint8_t* p = data->data() + 8;
  m = evade::odometry_t{};
  m.utime = be64(p);
  m.x = be_double(p + 8);
  m.y = be_double(p + 16);
  m.yaw = be_double(p + 24);
  m.v = be_double(p + 32);
  m.omega = be_double(p + 40);
  m.epoch = 0;
  *data = evade::bus::encode(m);
  return Outcome::kMigrated;
}

// Walks a length-prefixed LCM string; false when it runs past `end`.
bool skip_string(const uint8_t** p, const uint8_t* end) {
  if (end - *p < 4) return false;
  const int32_t n = be32(*p);
  if (n < 0 || end - *p - 4 < n) return false;
  *p += 4 + n;
  return true;
}

// The old sim_truth_t body ends right after its obstacles: the number of
// obstacles when `data` (fingerprint included) is exactly that, else -1.
int32_t old_sim_truth_obstacles(const std::vector<uint8_t>& data) {
  const uint8_t* p = data.data() + 8;  // past the fingerprint
  const uint8_t* end = data.data() + data.size();
  if (data.size() < 8 + 8 + 7 * 8 + 1) return -1;
  p += 8 + 7 * 8 + 1;  // utime, x, y, yaw, v, omega, footprint (2), obstacles_moving
  if (!skip_string(&p, end) || end - p < 4 * 8 + 4) return -1;
  p += 4 * 8;  // goal_x, goal_y, goal_tolerance, duration_s
  const int32_t n = be32(p);
  p += 4;
  for (int32_t i = 0; i < n; ++i) {
    if (end - p < 4) return -1;
    p += 4;  // id
    if (!skip_string(&p, end) || end - p < 9 * 8) return -1;
    p += 9 * 8;  // x, y, yaw, radius, length, width, height, vx, vy
  }
  return p == end && n >= 0 ? n : -1;
}

Outcome sim_truth_returns(std::vector<uint8_t>* data) {
  evade::sim_truth_t m;
  if (evade::bus::decode(data->data(), data->size(), &m)) return Outcome::kCurrent;
  const int32_t n = old_sim_truth_obstacles(*data);
  if (n < 0) return Outcome::kForeign;
  const std::vector<uint8_t> fingerprint = evade::bus::encode(evade::sim_truth_t{});
  std::copy(fingerprint.begin(), fingerprint.begin() + 8, data->begin());
  for (int32_t i = 0; i < n; ++i) data->insert(data->end(), {0xff, 0xff, 0xff, 0xff});  // -1
  return evade::bus::decode(data->data(), data->size(), &m) ? Outcome::kMigrated : Outcome::kForeign;
}

const Migration kMigrations[] = {
    {"odometry-epoch", "ODOMETRY", odometry_epoch},
    {"sim-truth-returns", "SIM_TRUTH", sim_truth_returns},
};

}  // namespace

int main(int argc, char** argv) {
  namespace bus = evade::bus;
  namespace fs = std::filesystem;
  CLI::App app{"evade log-migrate: carry a log across an appended-field lcmtypes change"};
  std::string name, in, out;
  bool force = false;
  std::vector<std::string> names;
  for (const Migration& m : kMigrations) names.push_back(m.name);
  app.add_option("migration", name, "one of: odometry-epoch, sim-truth-returns")->required()->check(CLI::IsMember(names));
  app.add_option("in", in, "input log")->required()->check(CLI::ExistingFile);
  app.add_option("out", out, "output log")->required();
  app.add_flag("--force", force, "replace OUT if it exists (also IN itself)");
  CLI11_PARSE(app, argc, argv);
  if (fs::exists(out) && !force) {
    std::fprintf(stderr, "log-migrate: %s exists; refusing to overwrite it without --force\n", out.c_str());
    return 2;
  }
  const Migration* migration = nullptr;
  for (const Migration& m : kMigrations)
    if (name == m.name) migration = &m;
  std::vector<bus::LogEvent> events = bus::read_log(in);
  size_t migrated = 0, current = 0;
  for (auto& e : events) {
    if (e.channel != migration->channel) continue;
    switch (migration->apply(&e.data)) {
      case Outcome::kMigrated: ++migrated; break;
      case Outcome::kCurrent: ++current; break;
      case Outcome::kForeign:
        std::fprintf(stderr, "log-migrate: a %s of %zu bytes is neither the old nor the current type; %s left alone\n",
                     migration->channel, e.data.size(), in.c_str());
        return 1;
    }
  }
  const std::string tmp = out + ".migrating";
  bus::write_log(tmp, events);
  fs::rename(tmp, out);
  std::printf("log-migrate: %s -> %s: %zu %s migrated, %zu already current, %zu events\n", in.c_str(), out.c_str(),
              migrated, migration->channel, current, events.size());
  return 0;
}
