#include "tools/mission/ports.h"

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

namespace cairn::mission {

namespace {

/// Binds 127.0.0.1:`port` (0: any) and returns the port bound, or -1.
int bind_port(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return -1;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons(uint16_t(port));
  // As the console binds (httplib sets SO_REUSEADDR): a port whose last connections linger in
  // TIME_WAIT after a previous mission is free to listen on again.
  const int reuse = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &reuse, sizeof(reuse));
  int result = -1;
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) == 0) {
    socklen_t len = sizeof(addr);
    getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
    result = ntohs(addr.sin_port);
  }
  close(fd);
  return result;
}

}  // namespace

bool port_is_free(int port) { return bind_port(port) == port; }
int free_port() { return bind_port(0); }

}  // namespace cairn::mission
