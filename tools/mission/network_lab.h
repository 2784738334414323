#pragma once
// An emulated radio link for the demo and tests (no netem in these kernels): the base station runs
// in its own network namespace, joined to the robots' side by a veth pair whose both ends drop a
// share of packets (nftables `numgen random`) and are rate-limited (tbf). Needs root, `ip`, `nft`
// and `tc`. The namespace and its rules are removed when the NetworkLab is destroyed.
#include <memory>
#include <string>
#include <vector>

namespace cairn::mission {

struct LinkOptions {
  double loss_pct = 0.0;  ///< packets dropped in each direction, 0..90
  int rate_kbit = 0;      ///< tbf rate per direction; 0 = unlimited
  int latency_ms = 200;   ///< tbf queue bound
};

class NetworkLab {
 public:
  /// nullptr with `error` when the lab cannot be set up (not root, tools missing, ...).
  static std::unique_ptr<NetworkLab> create(const LinkOptions& options, std::string* error);
  ~NetworkLab();
  NetworkLab(const NetworkLab&) = delete;
  NetworkLab& operator=(const NetworkLab&) = delete;

  /// Command prefix that runs a program inside the base station's namespace.
  std::vector<std::string> prefix() const { return {"/usr/sbin/ip", "netns", "exec", netns_}; }
  const std::string& robots_side_address() const { return host_address_; }
  const std::string& base_side_address() const { return lab_address_; }
  std::string describe() const;

 private:
  NetworkLab() = default;
  std::string netns_, veth_host_, veth_lab_, host_address_, lab_address_;
  LinkOptions options_;
};

}  // namespace cairn::mission
