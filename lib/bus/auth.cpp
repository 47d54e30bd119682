#include "bus/auth.h"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace evade::bus {
namespace {

constexpr size_t kMaxSenderChars = 31;
constexpr size_t kSeqBytes = 8;
constexpr size_t kHeadBytes = 16;  // fingerprint + utime

uint32_t be32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}
int64_t be64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return static_cast<int64_t>(v);
}
void put_be(std::vector<uint8_t>* out, uint64_t v, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) out->push_back(static_cast<uint8_t>(v >> (8 * i)));
}
bool sender_char(uint8_t c) { return std::isalnum(c) || c == '_' || c == '-' || c == '.'; }
bool valid_sender(const std::string& s) {
  return !s.empty() && s.size() <= kMaxSenderChars &&
         std::all_of(s.begin(), s.end(), [](char c) { return sender_char(static_cast<uint8_t>(c)); });
}

// |a - b| > limit, without overflow for any int64 stamps.
bool farther_than(int64_t a, int64_t b, int64_t limit) {
  const long double d = static_cast<long double>(a) - static_cast<long double>(b);
  return d > limit || d < -limit;
}

}  // namespace

const std::vector<std::string>& authenticated_channels() {
  static const std::vector<std::string> kChannels = {"CMD_VEL", "ESTOP", "ODOMETRY", "OBSTACLE_PREDICTIONS", "ROUTE"};
  return kChannels;
}

bool is_authenticated(const std::string& channel) {
  const auto& c = authenticated_channels();
  return std::find(c.begin(), c.end(), channel) != c.end();
}

AuthParams AuthParams::from_config(const config::Node& root) {
  return config::load<AuthParams>(root.section("bus").section("auth"));
}

std::string key_path(const AuthParams& params) {
  const char* env = std::getenv("EVADE_BUS_KEY");
  if (env && *env) return env;
  if (params.key_file.rfind("~/", 0) == 0) {
    const char* home = std::getenv("HOME");
    if (!home || !*home)
      throw KeyError("bus key: " + params.key_file + " names the home directory but $HOME is not set");
    return std::string(home) + params.key_file.substr(1);
  }
  return params.key_file;
}

std::vector<uint8_t> load_key(const std::string& path, bool owner_only) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw KeyError("bus key: no key file " + path + " (create one with: bash tools/setup key)");
  if (!S_ISREG(st.st_mode)) throw KeyError("bus key: " + path + " is not a regular file");
  if (owner_only && (st.st_mode & (S_IRWXG | S_IRWXO))) {
    std::ostringstream os;
    os << "bus key: " << path << " is accessible to group or others (mode " << std::oct << (st.st_mode & 07777)
       << "); only its owner may read it: chmod 600 " << path;
    throw KeyError(os.str());
  }
  std::ifstream in(path);
  if (!in) throw KeyError("bus key: cannot read " + path);
  std::string hex;
  for (char c; in.get(c);)
    if (!std::isspace(static_cast<unsigned char>(c))) hex.push_back(c);
  if (hex.size() % 2 != 0 ||
      !std::all_of(hex.begin(), hex.end(), [](char c) { return std::isxdigit(static_cast<unsigned char>(c)); }))
    throw KeyError("bus key: " + path + " is not hexadecimal text");
  std::vector<uint8_t> key;
  for (size_t i = 0; i < hex.size(); i += 2)
    key.push_back(static_cast<uint8_t>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  if (key.size() < kMinKeyBytes)
    throw KeyError("bus key: " + path + " holds " + std::to_string(key.size()) + " bytes; at least " +
                   std::to_string(kMinKeyBytes) + " are needed");
  return key;
}

bool parse_tail(const uint8_t* data, size_t size, AuthTail* out) {
  const size_t fixed = kSeqBytes + kMacBytes;
  // Shortest name first. Names have no zero bytes and a length's three
  // high bytes are zero, so at most one length fits (see lib/bus/README.md).
  for (size_t len = 1; len <= kMaxSenderChars + 1; ++len) {
    if (size < kHeadBytes + 4 + len + fixed) return false;
    const size_t name = size - fixed - len;
    if (data[name + len - 1] != 0 || be32(data + name - 4) != len) continue;
    if (!std::all_of(data + name, data + name + len - 1, sender_char)) continue;
    out->sender.assign(reinterpret_cast<const char*>(data + name), len - 1);
    out->seq = be64(data + size - fixed);
    out->sender_offset = name - 4;
    out->mac_offset = size - kMacBytes;
    return true;
  }
  return false;
}

HmacAuth::HmacAuth(std::vector<uint8_t> key, std::string sender, double window_s)
    : key_(std::move(key)), sender_(std::move(sender)), window_us_(static_cast<int64_t>(window_s * 1e6)) {
  if (!valid_sender(sender_)) throw std::invalid_argument("auth: '" + sender_ + "' is not a sender name");
  if (key_.size() < kMinKeyBytes) throw std::invalid_argument("auth: key shorter than 32 bytes");
}

void HmacAuth::mac(const std::string& channel, const uint8_t* data, size_t size, uint8_t out[kMacBytes]) const {
  std::vector<uint8_t> input(channel.begin(), channel.end());
  input.push_back(0);
  input.insert(input.end(), data, data + size);
  unsigned int n = 0;
  if (!HMAC(EVP_sha256(), key_.data(), static_cast<int>(key_.size()), input.data(), input.size(), out, &n) ||
      n != kMacBytes)
    throw std::runtime_error("auth: HMAC-SHA256 failed (libcrypto)");
}

bool HmacAuth::sign(const std::string& channel, int64_t now, std::vector<uint8_t>* data) {
  if (!is_authenticated(channel)) return true;
  AuthTail tail;
  if (!parse_tail(data->data(), data->size(), &tail)) return false;
  int64_t& last = sent_[channel];
  const int64_t seq = std::max(last + 1, now);
  last = seq;
  data->resize(tail.sender_offset);
  put_be(data, sender_.size() + 1, 4);
  data->insert(data->end(), sender_.begin(), sender_.end());
  data->push_back(0);
  put_be(data, static_cast<uint64_t>(seq), 8);
  uint8_t code[kMacBytes];
  mac(channel, data->data(), data->size(), code);
  data->insert(data->end(), code, code + kMacBytes);
  return true;
}

AuthVerdict HmacAuth::verify(const std::string& channel, const uint8_t* data, size_t size, int64_t now) {
  if (!is_authenticated(channel)) return AuthVerdict::kOk;
  AuthTail tail;
  if (!parse_tail(data, size, &tail) || tail.sender.empty()) return AuthVerdict::kUnsigned;
  uint8_t code[kMacBytes];
  mac(channel, data, tail.mac_offset, code);
  if (CRYPTO_memcmp(code, data + tail.mac_offset, kMacBytes) != 0) return AuthVerdict::kBadMac;
  if (farther_than(be64(data + 8), now, window_us_)) return AuthVerdict::kOutsideWindow;
  const std::string who = channel + '\0' + tail.sender;
  auto it = accepted_.find(who);
  if (it != accepted_.end() && tail.seq <= it->second) return AuthVerdict::kOldSeq;
  accepted_[who] = tail.seq;
  return AuthVerdict::kOk;
}

AuthSetup load_auth(const config::Node& root) {
  const AuthParams p = AuthParams::from_config(root);
  AuthSetup s;
  s.key = load_key(key_path(p));
  s.window_s = p.window_s;
  return s;
}

}  // namespace evade::bus
