// Authenticated channels (issue 20): HMAC-SHA256 with a shared key, a
// sequence number per sender and a time window on bus time.
//
// Wire format. Each authenticated type ends with the same three fields
// (lcmtypes/: cmd_vel_t, estop_t, odometry_t, path_t, prediction_list_t):
//
//   string  auth_sender;   // 1-31 characters of [A-Za-z0-9_.-]
//   int64_t auth_seq;
//   int8_t  auth_mac[32];
//
// and begins with `int64_t utime`. Being last, they are the last bytes of
// the LCM encoding: [u32 length][name][NUL][i64 seq][32 bytes mac]. The
// code is HMAC-SHA256(key, channel name, NUL, every byte of the encoding
// before auth_mac), so a message signed for one channel is no good on
// another. A core publishes these fields empty; the signer fills them.
//
// Checks, in order, each counted in HEALTH under its verdict_name():
// the tail parses (else auth_unsigned), the code matches (auth_bad_mac),
// |utime - bus time| <= window (auth_outside_window), and the sequence
// number is above the last accepted one from that sender on that channel
// (auth_old_seq). A signer numbers its messages max(last + 1, bus time in
// us), so a restarted sender continues above where it stopped.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bus/core.h"
#include "config/config.h"
#include "config/fields.h"

namespace evade::bus {

// The channels that carry authentication; a receiver acts on none of them
// unsigned. Fixed here (docs/SPEC.md), not configurable.
const std::vector<std::string>& authenticated_channels();
bool is_authenticated(const std::string& channel);

inline constexpr size_t kMacBytes = 32;
inline constexpr size_t kMinKeyBytes = 32;

// Parameters of the `bus.auth` section of the robot configuration.
struct AuthParams {
  std::string key_file = "~/.config/evade/bus.key";  // "~/" is the user's home; $EVADE_BUS_KEY overrides
  double window_s = 2.0;                             // |utime - bus time| accepted

  template <class V>
  void fields(V& v) {
    v.field("key_file", key_file);
    v.rule(!key_file.empty(), "key_file", "must name the key file");
    v.field("window_s", window_s, config::between(0.05, 60.0));
  }
  // root = the whole configuration; reads `bus.auth`.
  static AuthParams from_config(const config::Node& root);
};

// A key that cannot be used: missing, readable by group or others, not a
// regular file, or too short. The message says which and what to do.
class KeyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The key file's path: $EVADE_BUS_KEY when set, else key_file with a
// leading "~/" replaced by $HOME.
std::string key_path(const AuthParams& params);
// Reads a key file: hexadecimal text (whitespace ignored), at least
// kMinKeyBytes bytes. Throws KeyError unless it is a regular file with no
// permission bits for group or others (`owner_only` false skips that check:
// only for the public test key, see process-replay).
std::vector<uint8_t> load_key(const std::string& path, bool owner_only = true);

// What the parser finds at the end of an encoded message.
struct AuthTail {
  std::string sender;
  int64_t seq = 0;
  size_t sender_offset = 0;  // where the tail (the sender's length) begins
  size_t mac_offset = 0;     // where auth_mac begins (= size - kMacBytes)
};
// False when the bytes do not end with a well-formed tail.
bool parse_tail(const uint8_t* data, size_t size, AuthTail* out);

class HmacAuth : public Authenticator {
 public:
  // `sender` names this process in what it signs (see the field rules).
  HmacAuth(std::vector<uint8_t> key, std::string sender, double window_s);
  bool sign(const std::string& channel, int64_t now, std::vector<uint8_t>* data) override;
  AuthVerdict verify(const std::string& channel, const uint8_t* data, size_t size, int64_t now) override;
  const std::string& sender() const { return sender_; }

 private:
  void mac(const std::string& channel, const uint8_t* data, size_t size, uint8_t out[kMacBytes]) const;
  std::vector<uint8_t> key_;
  std::string sender_;
  int64_t window_us_;
  std::map<std::string, int64_t> sent_;      // channel -> last seq signed
  std::map<std::string, int64_t> accepted_;  // channel + NUL + sender -> last seq accepted
};

// The key of the configuration (key_path, load_key) and its window: what
// every process that signs or checks needs. Throws KeyError or ConfigError.
struct AuthSetup {
  std::vector<uint8_t> key;
  double window_s = 2.0;
  std::unique_ptr<HmacAuth> make(const std::string& sender) const {
    return std::make_unique<HmacAuth>(key, sender, window_s);
  }
};
AuthSetup load_auth(const config::Node& root);

}  // namespace evade::bus
