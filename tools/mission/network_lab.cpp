#include "tools/mission/network_lab.h"

#include <unistd.h>

#include <cstdlib>
#include <sstream>

namespace cairn::mission {
namespace {

bool run(const std::string& command, std::string* error) {
  const int rc = std::system((command + " >/dev/null 2>&1").c_str());
  if (rc != 0 && error) *error = "network lab: '" + command + "' failed";
  return rc == 0;
}

/// nftables drop rule and tbf qdisc on one interface, run in `ns_exec` (empty = this namespace).
bool shape(const std::string& ns_exec, const std::string& dev, const LinkOptions& o, std::string* error) {
  const std::string table = "cairn_lab_" + dev;
  if (o.loss_pct > 0) {
    std::ostringstream rule;
    rule << ns_exec << "nft add rule inet " << table << " out oifname " << dev << " numgen random mod 1000 '<' "
         << int(o.loss_pct * 10) << " drop";
    if (!run(ns_exec + "nft add table inet " + table, error) ||
        !run(ns_exec + "nft add chain inet " + table + " out '{ type filter hook output priority 0; }'", error) ||
        !run(rule.str(), error)) {
      return false;
    }
  }
  if (o.rate_kbit > 0) {
    std::ostringstream tbf;
    tbf << ns_exec << "tc qdisc add dev " << dev << " root tbf rate " << o.rate_kbit << "kbit burst 32kbit latency "
        << o.latency_ms << "ms";
    if (!run(tbf.str(), error)) return false;
  }
  return true;
}

}  // namespace

std::unique_ptr<NetworkLab> NetworkLab::create(const LinkOptions& options, std::string* error) {
  if (geteuid() != 0) {
    *error = "network lab: needs root (network namespaces, nftables, tc)";
    return nullptr;
  }
  if (access("/usr/sbin/ip", X_OK) != 0 || access("/usr/sbin/nft", X_OK) != 0 || access("/usr/sbin/tc", X_OK) != 0) {
    *error = "network lab: needs ip, nft and tc (Debian packages iproute2 and nftables)";
    return nullptr;
  }
  if (options.loss_pct < 0 || options.loss_pct > 90 || options.rate_kbit < 0) {
    *error = "network lab: loss must be 0..90 % and the rate >= 0 kbit/s";
    return nullptr;
  }
  std::unique_ptr<NetworkLab> lab(new NetworkLab());
  const int id = int(getpid() % 250) + 1;
  lab->options_ = options;
  lab->netns_ = "cairn_lab_" + std::to_string(getpid());
  lab->veth_host_ = "cairnh" + std::to_string(id);
  lab->veth_lab_ = "cairnl" + std::to_string(id);
  lab->host_address_ = "10.213." + std::to_string(id) + ".1";
  lab->lab_address_ = "10.213." + std::to_string(id) + ".2";
  const std::string in_lab = "ip netns exec " + lab->netns_ + " ";
  const bool ok = run("ip netns add " + lab->netns_, error) &&
                  run("ip link add " + lab->veth_host_ + " type veth peer name " + lab->veth_lab_, error) &&
                  run("ip link set " + lab->veth_lab_ + " netns " + lab->netns_, error) &&
                  run("ip addr add " + lab->host_address_ + "/24 dev " + lab->veth_host_, error) &&
                  run("ip link set " + lab->veth_host_ + " up", error) &&
                  run(in_lab + "ip addr add " + lab->lab_address_ + "/24 dev " + lab->veth_lab_, error) &&
                  run(in_lab + "ip link set " + lab->veth_lab_ + " up", error) &&
                  run(in_lab + "ip link set lo up", error) && shape("", lab->veth_host_, options, error) &&
                  shape(in_lab, lab->veth_lab_, options, error);
  if (!ok) return nullptr;  // the destructor removes what was made
  return lab;
}

NetworkLab::~NetworkLab() {
  if (netns_.empty()) return;
  std::string ignored;
  run("nft delete table inet cairn_lab_" + veth_host_, &ignored);
  run("ip link del " + veth_host_, &ignored);  // removes both ends of the pair
  run("ip netns del " + netns_, &ignored);
}

std::string NetworkLab::describe() const {
  std::ostringstream s;
  s << "radio link " << host_address_ << " <-> " << lab_address_ << ": " << options_.loss_pct << " % loss";
  if (options_.rate_kbit > 0) s << ", " << options_.rate_kbit << " kbit/s";
  s << " each way";
  return s.str();
}

}  // namespace cairn::mission
