#include "common/random_token.h"

#include <cstdio>
#include <fstream>
#include <vector>

namespace cairn {

std::string random_hex_token(int bytes) {
  std::ifstream random("/dev/urandom", std::ios::binary);
  std::vector<char> raw(size_t(bytes > 0 ? bytes : 0));
  random.read(raw.data(), std::streamsize(raw.size()));
  if (!random || raw.empty()) return "";
  std::string token;
  char hex[3];
  for (char b : raw) {
    std::snprintf(hex, sizeof hex, "%02x", unsigned(static_cast<unsigned char>(b)));
    token += hex;
  }
  return token;
}

}  // namespace cairn
