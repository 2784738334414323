#pragma once
// TCP ports on this machine's loopback for a mission's console (launcher, tests, benchmarks).

namespace cairn::mission {

/// True when nothing listens on `port` (127.0.0.1) right now.
bool port_is_free(int port);
/// A port free right now (the kernel's pick); -1 when none can be had.
int free_port();

}  // namespace cairn::mission
