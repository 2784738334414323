#pragma once
// A secret for a URL or an Authorization header (the console's operator token).
#include <string>

namespace cairn {

/// `bytes` random bytes from /dev/urandom as lowercase hex (2 x bytes digits); "" when there is no
/// randomness to read, so a caller turns the feature off rather than use a guessable secret.
std::string random_hex_token(int bytes = 16);

}  // namespace cairn
