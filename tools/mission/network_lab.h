#pragma once
// An emulated radio link for the demo and tests (no netem in these kernels): the base station runs
// in its own network namespace, joined to the robots' side by a veth pair whose both ends drop a
// share of packets (nftables `numgen random`) and are rate-limited (tbf). Needs root, `ip`, `nft`
// and `tc`. The namespace and its rules are removed when the NetworkLab is destroyed.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace cairn::mission {

struct LinkOptions {
  double loss_pct = 0.0;  ///< packets dropped in each direction, 0..90
  int rate_kbit = 0;      ///< tbf rate per direction; 0 = unlimited
  int latency_ms = 200;   ///< tbf queue bound
  double cut_at_s = -1;   ///< the link goes down this many seconds into the mission (< 0: never)
  double cut_for_s = 0;   ///< ... for this long
};

/// What one side put on the link: packets and bytes that crossed it, and those the emulated radio
/// lost (the loss rule) or the rate limit's queue dropped.
struct LinkDirection {
  uint64_t packets = 0, bytes = 0;
  uint64_t lost_packets = 0, lost_bytes = 0;
  uint64_t queue_dropped_packets = 0;
};

struct LinkTraffic {
  LinkDirection to_base;    ///< robots' side -> base station
  LinkDirection to_robots;  ///< base station -> robots' side
  /// Packets dropped (both ways) while a robot was out of range (set_process_cut), by robot id.
  std::map<int, uint64_t> out_of_range_packets;
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
  /// Runs `work` on a thread inside the base station's namespace and waits for it: what the operator
  /// does at the base (the mission's progress polls of its console) stays off the emulated radio.
  void run_inside(const std::function<void()>& work) const;
  /// Drops every packet both ways (true) or lets them pass again (false): a radio out of range.
  bool set_cut(bool cut, std::string* error);
  /// Drops (true) or lets pass again (false) one process's traffic both ways: a robot out of range.
  /// The process stays in the robots' namespace (a namespace of its own would cost the shared
  /// memory its sensor topics travel on); its UDP ports, read from /proc, pick its packets out.
  bool set_process_cut(int robot, int pid, bool cut, std::string* error);
  /// The link's counters so far (read from the devices, the loss rules and the queues).
  LinkTraffic traffic() const;

 private:
  NetworkLab() = default;
  std::string netns_, veth_host_, veth_lab_, host_address_, lab_address_;
  LinkOptions options_;
  /// Packets a robot's cut dropped, both ways, counted when its cut was lifted (see traffic()).
  std::map<int, uint64_t> out_of_range_packets_;
  std::vector<int> robots_cut_;  ///< robots whose tables set_process_cut made
};

/// The UDP ports of a process's sockets that no other socket shares (a port bound by several, like
/// DDS's multicast discovery port, would cut others too). Empty when the process is gone.
std::vector<int> exclusive_udp_ports(int pid);

}  // namespace cairn::mission
