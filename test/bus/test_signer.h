// Signing in tests with the test-only key that ctest names in
// $EVADE_BUS_KEY (cmake/Testing.cmake), as a process of the stack would.
#pragma once

#include <cstdlib>
#include <string>
#include <vector>

#include "bus/auth.h"
#include "bus/core.h"

namespace evade::bus::testing {

inline HmacAuth test_signer(const std::string& sender) {
  const char* path = std::getenv("EVADE_BUS_KEY");
  return HmacAuth(load_key(path ? path : ""), sender, 2.0);
}

// The message encoded and signed for `channel` at bus time `now`.
template <class Msg>
std::vector<uint8_t> signed_bytes(HmacAuth& signer, const std::string& channel, const Msg& msg, int64_t now) {
  std::vector<uint8_t> data = encode(msg);
  if (!signer.sign(channel, now, &data)) std::abort();
  return data;
}

}  // namespace evade::bus::testing
