// log-migrate: carries a log across a change of lcmtypes that only
// appended fields, so that golden logs need not be recorded again.
//
//   log-migrate MIGRATION IN.lcmlog OUT.lcmlog [--force]
//   log-migrate auth-sign IN.lcmlog OUT.lcmlog [--config F] [--force]
//
// odometry-epoch (issue 20): ODOMETRY encoded before odometry_t gained
// `int64_t epoch` (fingerprint, utime, x, y, yaw, v, omega: 56 bytes) is
// re-encoded with the current type and epoch 0 (one frame throughout, as
// the recording was).
// plan-predictions-utime (issue 18): PLAN encoded before plan_t gained
// `int64_t predictions_utime` (its old fingerprint 0x9306470e7bded3f4) gets
// the current fingerprint and predictions_utime -1 (not recorded).
// sim-truth-returns (issue 23): SIM_TRUTH encoded before sim_truth_t gained
// `int32_t lidar_returns[num_obstacles]` gets the current fingerprint and
// -1 (not recorded) for every obstacle.
// auth-sign (issue 20): CMD_VEL, ODOMETRY, OBSTACLE_PREDICTIONS and ROUTE
// encoded before their types gained the authentication fields (lib/bus/
// auth.h), or current but never signed, get the current fingerprint, the
// fields, and a signature made with the configured key ($EVADE_BUS_KEY,
// else bus.auth.key_file) at the event's timestamp, as their publisher
// (planner, base_driver, predictor, route) would have signed them live.
// Every other event is copied as it is. OUT may be IN only with --force (it
// is written to a temporary file first).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>

#include "bus/auth.h"
#include "bus/core.h"
#include "bus/log.h"
#include "bus/process_main.h"
#include "config/config.h"
#include "config/robot_profile.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/path_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/prediction_list_t.hpp"
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
void put_be64(int64_t v, uint8_t* p) {
  for (int i = 7; i >= 0; --i, v = static_cast<int64_t>(static_cast<uint64_t>(v) >> 8)) p[i] = v & 0xff;
}

// One migration: the channel it rewrites and, for a message that is not of
// the current type, the rewrite (false: neither the old nor the current type).
struct Migration {
  std::string channel;
  std::function<bool(std::vector<uint8_t>*)> rewrite;
};

constexpr size_t kOldOdometrySize = 8 + 8 + 5 * 8;

bool odometry_epoch(std::vector<uint8_t>* data) {
  if (data->size() != kOldOdometrySize) return false;
  const uint8_t* p = data->data() + 8;
  evade::odometry_t m{};
  m.utime = be64(p);
  m.x = be_double(p + 8);
  m.y = be_double(p + 16);
  m.yaw = be_double(p + 24);
  m.v = be_double(p + 32);
  m.omega = be_double(p + 40);
  m.epoch = 0;
  *data = evade::bus::encode(m);
  return true;
}

constexpr int64_t kOldPlanHash = static_cast<int64_t>(0x9306470e7bded3f4ULL);

bool plan_predictions_utime(std::vector<uint8_t>* data) {
  if (data->size() < 8 || be64(data->data()) != kOldPlanHash) return false;
  std::vector<uint8_t> out = *data;
  put_be64(evade::plan_t::getHash(), out.data());
  out.resize(out.size() + 8);
  put_be64(-1, out.data() + out.size() - 8);  // predictions_utime: not recorded
  evade::plan_t check;
  if (!evade::bus::decode(out.data(), out.size(), &check)) return false;
  *data = std::move(out);
  return true;
}

int32_t be32(const uint8_t* p) {
  return static_cast<int32_t>((uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | p[3]);
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

bool sim_truth_returns(std::vector<uint8_t>* data) {
  const int32_t n = old_sim_truth_obstacles(*data);
  if (n < 0) return false;
  std::vector<uint8_t> out = *data;
  put_be64(evade::sim_truth_t::getHash(), out.data());
  for (int32_t i = 0; i < n; ++i) out.insert(out.end(), {0xff, 0xff, 0xff, 0xff});  // -1: not recorded
  evade::sim_truth_t check;
  if (!evade::bus::decode(out.data(), out.size(), &check)) return false;
  *data = std::move(out);
  return true;
}

const std::map<std::string, Migration>& migrations() {
  static const std::map<std::string, Migration> m = {
      {"odometry-epoch", Migration{"ODOMETRY", odometry_epoch}},
      {"plan-predictions-utime", Migration{"PLAN", plan_predictions_utime}},
      {"sim-truth-returns", Migration{"SIM_TRUTH", sim_truth_returns}},
  };
  return m;
}

// True when the bytes already decode as the channel's current type.
bool current(const std::string& channel, const std::vector<uint8_t>& data) {
  if (channel == "ODOMETRY") {
    evade::odometry_t m;
    return evade::bus::decode(data.data(), data.size(), &m);
  }
  if (channel == "SIM_TRUTH") {
    evade::sim_truth_t m;
    return evade::bus::decode(data.data(), data.size(), &m);
  }
  evade::plan_t m;
  return evade::bus::decode(data.data(), data.size(), &m);
}

template <class Msg>
struct AuthType {
  // The message with the authentication fields appended empty; false when
  // the bytes are neither the old type nor the current one. *was_current:
  // it is current and signed already.
  static bool upgrade(std::vector<uint8_t>* data, bool* was_current) {
    Msg m;
    if (evade::bus::decode(data->data(), data->size(), &m)) {
      *was_current = !m.auth_sender.empty();  // current but never signed: sign it
      return true;
    }
    const std::vector<uint8_t> fresh = evade::bus::encode(Msg{});
    std::vector<uint8_t> out(fresh.begin(), fresh.begin() + 8);          // the current fingerprint
    out.insert(out.end(), data->begin() + 8, data->end());               // the old fields
    out.insert(out.end(), fresh.end() - (4 + 1 + 8 + 32), fresh.end());  // empty auth fields
    if (data->size() < 8 || !evade::bus::decode(out.data(), out.size(), &m)) return false;
    *data = std::move(out);
    *was_current = false;
    return true;
  }
};

int migrate_auth_sign(std::vector<evade::bus::LogEvent>* events, const evade::bus::CommonOptions& opts) {
  namespace bus = evade::bus;
  const std::string path = opts.config_path.empty() ? evade::config::default_config_path() : opts.config_path;
  const bus::AuthSetup keys = bus::load_auth(evade::config::load_robot_config(path, {opts.robot, ""}));
  struct Kind {
    std::string channel, sender;
    bool (*upgrade)(std::vector<uint8_t>*, bool*);
    std::unique_ptr<bus::HmacAuth> auth;
    size_t migrated = 0, current = 0;
  };
  std::vector<Kind> kinds;
  kinds.push_back({"CMD_VEL", "planner", &AuthType<evade::cmd_vel_t>::upgrade, nullptr});
  kinds.push_back({"ODOMETRY", "base_driver", &AuthType<evade::odometry_t>::upgrade, nullptr});
  kinds.push_back({"OBSTACLE_PREDICTIONS", "predictor", &AuthType<evade::prediction_list_t>::upgrade, nullptr});
  kinds.push_back({"ROUTE", "route", &AuthType<evade::path_t>::upgrade, nullptr});
  for (auto& k : kinds) k.auth = keys.make(k.sender);
  for (auto& e : *events) {
    for (auto& k : kinds) {
      if (e.channel != k.channel) continue;
      bool current = false;
      if (!k.upgrade(&e.data, &current)) {
        std::fprintf(stderr, "log-migrate: a %s of %zu bytes is neither the old nor the current type\n",
                     e.channel.c_str(), e.data.size());
        return 1;
      }
      if (current) {
        ++k.current;
        continue;
      }
      k.auth->sign(e.channel, e.timestamp, &e.data);
      ++k.migrated;
    }
  }
  for (const auto& k : kinds)
    std::printf("log-migrate: %s: %zu signed as %s, %zu already current\n", k.channel.c_str(), k.migrated,
                k.sender.c_str(), k.current);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  namespace bus = evade::bus;
  namespace fs = std::filesystem;
  CLI::App app{"evade log-migrate: carry a log across an appended-field lcmtypes change"};
  std::string name, in, out;
  bool force = false;
  std::vector<std::string> names;
  for (const auto& [n, m] : migrations()) names.push_back(n);
  names.push_back("auth-sign");
  bus::CommonOptions opts;
  app.add_option("migration", name, "odometry-epoch | plan-predictions-utime | sim-truth-returns | auth-sign")
      ->required()
      ->check(CLI::IsMember(names));
  bus::add_robot_options(app, opts, false);  // auth-sign: --config naming the key (bus.auth), --robot
  app.add_option("in", in, "input log")->required()->check(CLI::ExistingFile);
  app.add_option("out", out, "output log")->required();
  app.add_flag("--force", force, "replace OUT if it exists (also IN itself)");
  CLI11_PARSE(app, argc, argv);
  if (fs::exists(out) && !force) {
    std::fprintf(stderr, "log-migrate: %s exists; refusing to overwrite it without --force\n", out.c_str());
    return 2;
  }
  std::vector<bus::LogEvent> events = bus::read_log(in);
  if (name == "auth-sign") {
    int status = 0;
    try {
      status = migrate_auth_sign(&events, opts);
    } catch (const std::exception& e) {  // a bad configuration or key
      std::fprintf(stderr, "log-migrate: %s\n", e.what());
      return 2;
    }
    if (status != 0) return status;
    const std::string tmp = out + ".migrating";
    bus::write_log(tmp, events);
    fs::rename(tmp, out);
    std::printf("log-migrate: %s -> %s: %zu events\n", in.c_str(), out.c_str(), events.size());
    return 0;
  }
  const Migration& mig = migrations().at(name);
  size_t migrated = 0, already = 0;
  for (auto& e : events) {
    if (e.channel != mig.channel) continue;
    if (current(e.channel, e.data)) {
      ++already;
      continue;
    }
    if (!mig.rewrite(&e.data)) {
      std::fprintf(stderr, "log-migrate: a %s of %zu bytes is neither the old nor the current type\n",
                   e.channel.c_str(), e.data.size());
      return 1;
    }
    ++migrated;
  }
  const std::string tmp = out + ".migrating";
  bus::write_log(tmp, events);
  fs::rename(tmp, out);
  std::printf("log-migrate: %s -> %s: %zu %s migrated, %zu already current, %zu events\n", in.c_str(), out.c_str(),
              migrated, mig.channel.c_str(), already, events.size());
  return 0;
}
