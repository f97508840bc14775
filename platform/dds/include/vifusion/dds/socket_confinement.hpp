#pragma once
// Holding Cyclone DDS 0.10 to the network interface its configuration names, in the kernel.
//
// Cyclone 0.10 binds its transmit socket to the configured interface's address, but its unicast
// receive sockets to 0.0.0.0 (INADDR_ANY) whatever the configuration says, and has no option against
// it: a datagram sent to the domain's ports on any interface would reach it. After the domain exists,
// vifusion binds every UDP socket Cyclone opened to that one interface with SO_BINDTODEVICE: the
// kernel then delivers to them only datagrams that arrived on it and sends only through it
// (`ss -uapn` shows 0.0.0.0%lo:7410). Linux >= 5.7 lets an unprivileged process do this once per
// socket; no capability is needed.
//
// Which interface: the one whose address Cyclone bound its transmit sockets to — Cyclone's own
// reading of the configuration, so no second parser of its XML can disagree with it. A configuration
// with several interfaces cannot be confined to one device; it is left as Cyclone made it and the
// result says so (the systemd units' IPAddressAllow= still filters what reaches the service).

#include <set>
#include <string>

namespace vifusion::dds {

/// File descriptors of this process's UDP sockets (IPv4 and IPv6), from /proc/self/fd.
std::set<int> udpSocketDescriptors();

struct SocketConfinement {
  /// The interface every socket was bound to; empty when the sockets were left as Cyclone made them.
  std::string interface;
  /// How many UDP sockets were bound to `interface`.
  int sockets = 0;
  /// One line for the log: what was bound where, or why nothing was.
  std::string description;
};

/// Binds the UDP sockets opened since `before` (a udpSocketDescriptors() snapshot taken just before
/// the DDS domain was created) to the single interface whose address their bound sockets use.
/// Throws vifusion::Error naming the socket and the errno when the kernel refuses the binding.
SocketConfinement confineNewUdpSockets(const std::set<int>& before);

}  // namespace vifusion::dds
