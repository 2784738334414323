#include "tools/mission/network_lab.h"

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <thread>
#include <tuple>

namespace cairn::mission {
namespace {

bool run(const std::string& command, std::string* error) {
  const int rc = std::system((command + " >/dev/null 2>&1").c_str());
  if (rc != 0 && error) *error = "network lab: '" + command + "' failed";
  return rc == 0;
}

/// A table of its own holding one drop rule on the output hook, ahead of the loss rules (priority -1),
/// made to cut and deleted to restore; `rule` is what precedes "drop".
bool add_drop_table(const std::string& ns_exec, const std::string& table, const std::string& rule, std::string* error) {
  return run(ns_exec + "nft add table inet " + table, error) &&
         run(ns_exec + "nft add chain inet " + table + " out '{ type filter hook output priority -1; }'", error) &&
         run(ns_exec + "nft add rule inet " + table + " out " + rule + " drop", error);
}

/// nftables drop rule and tbf qdisc on one interface, run in `ns_exec` (empty = this namespace).
bool shape(const std::string& ns_exec, const std::string& dev, const LinkOptions& o, std::string* error) {
  const std::string table = "cairn_lab_" + dev;
  if (o.loss_pct > 0) {
    std::ostringstream rule;
    rule << ns_exec << "nft add rule inet " << table << " out oifname " << dev << " numgen random mod 1000 '<' "
         << int(o.loss_pct * 10) << " counter drop";
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

/// Standard output of `command` (empty when it fails).
std::string output_of(const std::string& command) {
  std::string text;
  if (FILE* pipe = ::popen((command + " 2>/dev/null").c_str(), "r")) {
    char buf[4096];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) text.append(buf, n);
    ::pclose(pipe);
  }
  return text;
}

/// The first number after `key` in `text` (0 when absent).
uint64_t number_after(const std::string& text, const std::string& key) {
  const size_t at = text.find(key);
  return at == std::string::npos ? 0 : std::strtoull(text.c_str() + at + key.size(), nullptr, 10);
}

/// What left one end of the link: the device's counters, the loss rule's counter, the queue's drops.
LinkDirection direction(const std::string& ns_exec, const std::string& dev) {
  LinkDirection d;
  const std::string stats = "/sys/class/net/" + dev + "/statistics/";
  d.packets = number_after(output_of(ns_exec + "cat " + stats + "tx_packets"), "");
  d.bytes = number_after(output_of(ns_exec + "cat " + stats + "tx_bytes"), "");
  const std::string rule = output_of(ns_exec + "nft list table inet cairn_lab_" + dev);
  d.lost_packets = number_after(rule, "counter packets ");
  d.lost_bytes = number_after(rule, " bytes ");
  d.queue_dropped_packets = number_after(output_of(ns_exec + "tc -s qdisc show dev " + dev), "(dropped ");
  return d;
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
  if (options.loss_pct < 0 || options.loss_pct > 90 || options.rate_kbit < 0 || !(options.cut_for_s >= 0)) {
    *error = "network lab: loss must be 0..90 %, the rate >= 0 kbit/s and a cut >= 0 s";
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
  run("nft delete table inet cairn_cut_" + veth_host_, &ignored);
  for (int robot : robots_cut_)
    run("nft delete table inet cairn_radio" + std::to_string(robot) + "_" + veth_host_, &ignored);
  run("ip link del " + veth_host_, &ignored);  // removes both ends of the pair
  run("ip netns del " + netns_, &ignored);
}

void NetworkLab::run_inside(const std::function<void()>& work) const {
  std::thread([&] {
    // setns() moves only the calling thread; a thread of its own keeps the launcher where it is.
    const int fd = ::open(("/var/run/netns/" + netns_).c_str(), O_RDONLY | O_CLOEXEC);
    const bool inside = fd >= 0 && ::setns(fd, CLONE_NEWNET) == 0;
    if (fd >= 0) ::close(fd);
    if (inside) work();
  }).join();
}

bool NetworkLab::set_cut(bool cut, std::string* error) {
  // A drop table on each side (the loss rules stay).
  const std::string in_lab = "ip netns exec " + netns_ + " ";
  for (const auto& [ns_exec, dev] : {std::pair{std::string(), veth_host_}, std::pair{in_lab, veth_lab_}}) {
    const std::string table = "cairn_cut_" + dev;
    const bool ok = cut ? add_drop_table(ns_exec, table, "oifname " + dev, error)
                        : run(ns_exec + "nft delete table inet " + table, error);
    if (!ok) return false;
  }
  return true;
}

bool NetworkLab::set_process_cut(int robot, int pid, bool cut, std::string* error) {
  const std::string in_lab = "ip netns exec " + netns_ + " ";
  const std::string tag = "cairn_radio" + std::to_string(robot) + "_";
  std::string ports;
  if (cut) {
    for (int port : exclusive_udp_ports(pid)) ports += (ports.empty() ? "" : ", ") + std::to_string(port);
    if (ports.empty()) {
      if (error)
        *error = "network lab: robot " + std::to_string(robot) + "'s process " + std::to_string(pid) +
                 " has no UDP socket of its own";
      return false;
    }
  }
  // Its packets leave the robots' side from its ports and the base's side towards them.
  for (const auto& [ns_exec, dev, match] : {std::tuple{std::string(), veth_host_, std::string("udp sport")},
                                            std::tuple{in_lab, veth_lab_, std::string("udp dport")}}) {
    const std::string table = tag + dev;
    if (cut) {
      run(ns_exec + "nft delete table inet " + table, nullptr);  // a cut with old ports, if any
      if (!add_drop_table(ns_exec, table, "oifname " + dev + " " + match + " '{ " + ports + " }' counter", error))
        return false;
    } else {
      const uint64_t dropped = number_after(output_of(ns_exec + "nft list table inet " + table), "counter packets ");
      if (!run(ns_exec + "nft delete table inet " + table, error)) return false;
      out_of_range_packets_[robot] += dropped;
    }
  }
  if (cut && std::find(robots_cut_.begin(), robots_cut_.end(), robot) == robots_cut_.end())
    robots_cut_.push_back(robot);
  return true;
}

std::vector<int> exclusive_udp_ports(int pid) {
  // The process's socket inodes, from its open files ("socket:[12345]").
  std::set<unsigned long> inodes;
  std::error_code ec;
  for (const auto& fd : std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec)) {
    const std::string target = std::filesystem::read_symlink(fd.path(), ec).string();
    if (!ec && target.rfind("socket:[", 0) == 0) inodes.insert(std::stoul(target.substr(8)));
  }
  // Every UDP socket of its namespace: "sl local_address(hex ip:hex port) ... inode".
  std::map<int, int> sockets_on_port;
  std::set<int> own;
  std::istringstream table(output_of("cat /proc/" + std::to_string(pid) + "/net/udp"));
  std::string line;
  std::getline(table, line);  // the header
  while (std::getline(table, line)) {
    std::istringstream f(line);
    std::string sl, local, remote, state, queues, timer, retransmits, uid, timeout;
    unsigned long inode = 0;
    if (!(f >> sl >> local >> remote >> state >> queues >> timer >> retransmits >> uid >> timeout >> inode)) continue;
    const size_t colon = local.find(':');
    if (colon == std::string::npos) continue;
    const int port = int(std::strtol(local.c_str() + colon + 1, nullptr, 16));
    ++sockets_on_port[port];
    if (inodes.count(inode)) own.insert(port);
  }
  std::vector<int> out;
  for (int port : own) {
    if (sockets_on_port[port] == 1) out.push_back(port);
  }
  return out;
}

LinkTraffic NetworkLab::traffic() const {
  const std::string in_lab = "ip netns exec " + netns_ + " ";
  LinkTraffic t{direction("", veth_host_), direction(in_lab, veth_lab_), out_of_range_packets_};
  for (int robot : robots_cut_) {
    // Cuts still in force: their tables' counters.
    const std::string tag = "cairn_radio" + std::to_string(robot) + "_";
    t.out_of_range_packets[robot] +=
        number_after(output_of("nft list table inet " + tag + veth_host_), "counter packets ") +
        number_after(output_of(in_lab + "nft list table inet " + tag + veth_lab_), "counter packets ");
  }
  return t;
}

std::string NetworkLab::describe() const {
  std::ostringstream s;
  s << "radio link " << host_address_ << " <-> " << lab_address_ << ": " << options_.loss_pct << " % loss";
  if (options_.rate_kbit > 0) s << ", " << options_.rate_kbit << " kbit/s";
  s << " each way";
  if (options_.cut_at_s >= 0) s << "; cut from " << options_.cut_at_s << " s for " << options_.cut_for_s << " s";
  return s.str();
}

}  // namespace cairn::mission
