#include "dds/identity.h"

#include <openssl/evp.h>
#include <openssl/x509.h>

#include <cstring>
#include <memory>

namespace cairn::dds {

std::string robot_identity(int32_t robot_id) { return "robot" + std::to_string(robot_id); }

bool authenticated_as(const GuidPrefix& prefix, const std::string& identity) {
  // The subject as deploy/security/make_certs.sh writes it (-subj "/O=Cairn/CN=NAME", UTF8 strings).
  std::unique_ptr<X509_NAME, decltype(&X509_NAME_free)> name(X509_NAME_new(), X509_NAME_free);
  if (!name) return false;
  auto add = [&](const char* field, const std::string& value) {
    return X509_NAME_add_entry_by_txt(name.get(), field, MBSTRING_UTF8,
                                      reinterpret_cast<const unsigned char*>(value.c_str()), -1, -1, 0) == 1;
  };
  if (!add("O", "Cairn") || !add("CN", identity)) return false;
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (!X509_NAME_digest(name.get(), EVP_sha256(), md, &length) || length < 6) return false;
  // The prefix's first bit is 1; its next 47 bits are the digest's first 47 (the spec's layout).
  if ((prefix[0] & 0x80) == 0) return false;
  unsigned char bits[6];
  for (int i = 0; i < 6; ++i) bits[i] = uint8_t(prefix[i] << 1) | (i < 5 ? uint8_t(prefix[i + 1] >> 7) : 0);
  md[5] &= 0xFE;
  return std::memcmp(md, bits, 6) == 0;
}

}  // namespace cairn::dds
