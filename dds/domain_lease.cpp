#include "dds/domain_lease.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace cairn::dds {

std::unique_ptr<DomainLease> DomainLease::claim(const DomainLeaseOptions& options, std::string* error) {
  std::string last_error;
  for (int domain = options.first_domain; domain <= options.last_domain; ++domain) {
    const std::string path = options.lock_dir + "/cairn-dds-domain-" + std::to_string(domain) + ".lock";
    // O_CLOEXEC: child processes (agents, base) must not keep the hold after the parent is gone.
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) {
      last_error = "cannot open " + path + ": " + std::strerror(errno);
      continue;
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return std::unique_ptr<DomainLease>(new DomainLease(domain, fd));
    ::close(fd);
  }
  if (error) {
    *error = "no free DDS domain in " + std::to_string(options.first_domain) + ".." +
             std::to_string(options.last_domain) + (last_error.empty() ? "" : " (" + last_error + ")");
  }
  return nullptr;
}

DomainLease::~DomainLease() { ::close(fd_); }

}  // namespace cairn::dds
