#pragma once
// A DDS domain id this process holds for its lifetime, so that missions and tests running at the
// same time on one host never share a domain (a shared domain lets one mission's robots join
// another's base station). The hold is an flock() on a per-domain file; the kernel drops it when
// the process exits, however it exits, so a crashed mission never leaves a domain taken.
#include <memory>
#include <string>

namespace cairn::dds {

struct DomainLeaseOptions {
  int first_domain = 1;   ///< 0 is the default of hand-started agents and bases: left alone
  int last_domain = 200;  ///< UDP ports stay below 65535 up to 232
  std::string lock_dir = "/tmp";
};

class DomainLease {
 public:
  /// The lowest free domain in [first, last]; nullptr with `error` set when all are held or the
  /// lock folder cannot be written.
  static std::unique_ptr<DomainLease> claim(const DomainLeaseOptions& options, std::string* error);
  ~DomainLease();
  DomainLease(const DomainLease&) = delete;
  DomainLease& operator=(const DomainLease&) = delete;

  int domain_id() const { return domain_id_; }

 private:
  DomainLease(int domain_id, int fd) : domain_id_(domain_id), fd_(fd) {}
  int domain_id_;
  int fd_;
};

}  // namespace cairn::dds
