#pragma once
// Who wrote a sample, as DDS Security authenticated it. Under the builtin PKI-DH authentication a
// participant's GUID prefix begins with 47 bits of the SHA-256 of its certificate's subject name
// (DDS Security 1.1, 9.3.3); Fast DDS refuses a handshake whose GUID does not match the certificate
// it shows, and every message of an authenticated participant is protected with keys bound to that
// GUID. So the GUID prefix of a sample's writer says which team certificate it holds, and the base
// can check that a sample claiming robot N comes from the holder of robot N's certificate.
#include <array>
#include <cstdint>
#include <string>

namespace cairn::dds {

/// A participant's GUID prefix (the first 12 bytes of every GUID of its readers and writers).
using GuidPrefix = std::array<uint8_t, 12>;

/// The identity name make_certs.sh gives robot `robot_id` (its certificate's CN): "robot<N>".
std::string robot_identity(int32_t robot_id);

/// True when a participant with `prefix` authenticated with a certificate whose subject is
/// make_certs.sh's for `identity` (O=Cairn, CN=identity).
bool authenticated_as(const GuidPrefix& prefix, const std::string& identity);

}  // namespace cairn::dds
