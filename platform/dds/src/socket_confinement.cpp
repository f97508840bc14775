#include "vifusion/dds/socket_confinement.hpp"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "vifusion/core/error.hpp"

namespace vifusion::dds {
namespace {

int socketOption(int fd, int option) {
  int value = -1;
  socklen_t length = sizeof(value);
  return getsockopt(fd, SOL_SOCKET, option, &value, &length) == 0 ? value : -1;
}

bool isUdpSocket(int fd) {
  struct stat status {};
  if (fstat(fd, &status) != 0 || !S_ISSOCK(status.st_mode)) return false;
  const int family = socketOption(fd, SO_DOMAIN);
  return (family == AF_INET || family == AF_INET6) && socketOption(fd, SO_TYPE) == SOCK_DGRAM &&
         socketOption(fd, SO_PROTOCOL) == IPPROTO_UDP;
}

std::optional<sockaddr_storage> localAddress(int fd) {
  sockaddr_storage address{};
  socklen_t length = sizeof(address);
  if (getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0) return std::nullopt;
  return address;
}

bool isWildcard(const sockaddr_storage& address) {
  if (address.ss_family == AF_INET) {
    return reinterpret_cast<const sockaddr_in&>(address).sin_addr.s_addr == htonl(INADDR_ANY);
  }
  const auto& ipv6 = reinterpret_cast<const sockaddr_in6&>(address);
  return IN6_IS_ADDR_UNSPECIFIED(&ipv6.sin6_addr);
}

bool sameHost(const sockaddr_storage& bound, const sockaddr* interface_address) {
  if (interface_address == nullptr || interface_address->sa_family != bound.ss_family) return false;
  if (bound.ss_family == AF_INET) {
    return reinterpret_cast<const sockaddr_in&>(bound).sin_addr.s_addr ==
           reinterpret_cast<const sockaddr_in*>(interface_address)->sin_addr.s_addr;
  }
  return std::memcmp(&reinterpret_cast<const sockaddr_in6&>(bound).sin6_addr,
                     &reinterpret_cast<const sockaddr_in6*>(interface_address)->sin6_addr, sizeof(in6_addr)) == 0;
}

/// "127.0.0.1:7410" or "[::1]:7410".
std::string describe(const sockaddr_storage& address) {
  char text[INET6_ADDRSTRLEN] = {};
  if (address.ss_family == AF_INET) {
    const auto& ipv4 = reinterpret_cast<const sockaddr_in&>(address);
    inet_ntop(AF_INET, &ipv4.sin_addr, text, sizeof(text));
    return std::string(text) + ":" + std::to_string(ntohs(ipv4.sin_port));
  }
  const auto& ipv6 = reinterpret_cast<const sockaddr_in6&>(address);
  inet_ntop(AF_INET6, &ipv6.sin6_addr, text, sizeof(text));
  return "[" + std::string(text) + "]:" + std::to_string(ntohs(ipv6.sin6_port));
}

/// Names of the interfaces owning the addresses the given sockets are bound to (wildcards skipped).
std::set<std::string> interfacesOfBoundAddresses(const std::vector<sockaddr_storage>& addresses) {
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) {
    throw Error(std::string("DDS socket confinement: cannot list network interfaces: ") + std::strerror(errno));
  }
  const std::unique_ptr<ifaddrs, decltype(&freeifaddrs)> owner(list, &freeifaddrs);
  std::set<std::string> names;
  for (const sockaddr_storage& address : addresses) {
    if (isWildcard(address)) continue;
    for (const ifaddrs* entry = list; entry != nullptr; entry = entry->ifa_next) {
      if (sameHost(address, entry->ifa_addr)) names.insert(entry->ifa_name);
    }
  }
  return names;
}

std::string joined(const std::set<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

}  // namespace

std::set<int> udpSocketDescriptors() {
  std::set<int> descriptors;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd")) {
    const std::string name = entry.path().filename().string();
    const int fd = std::stoi(name);
    if (isUdpSocket(fd)) descriptors.insert(fd);
  }
  return descriptors;
}

SocketConfinement confineNewUdpSockets(const std::set<int>& before) {
  std::vector<int> fresh;
  std::vector<sockaddr_storage> addresses;
  for (const int fd : udpSocketDescriptors()) {
    if (before.count(fd) != 0) continue;
    const std::optional<sockaddr_storage> address = localAddress(fd);
    if (!address) continue;
    fresh.push_back(fd);
    addresses.push_back(*address);
  }
  SocketConfinement result;
  if (fresh.empty()) {
    result.description = "DDS opened no UDP socket: nothing to confine";
    return result;
  }
  const std::set<std::string> interfaces = interfacesOfBoundAddresses(addresses);
  if (interfaces.size() != 1) {
    result.description = interfaces.empty()
                             ? "DDS sockets not confined: none is bound to an interface's address"
                             : "DDS sockets not confined to one interface: the configuration uses " +
                                   joined(interfaces) + " (the units' IPAddressAllow= filters what reaches them)";
    return result;
  }
  result.interface = *interfaces.begin();
  for (std::size_t i = 0; i < fresh.size(); ++i) {
    if (setsockopt(fresh[i], SOL_SOCKET, SO_BINDTODEVICE, result.interface.c_str(),
                   static_cast<socklen_t>(result.interface.size())) != 0) {
      throw Error("DDS socket confinement: binding the UDP socket at " + describe(addresses[i]) + " to interface " +
                  result.interface + " failed: " + std::strerror(errno) +
                  (errno == EPERM ? " (Linux before 5.7 needs CAP_NET_RAW for SO_BINDTODEVICE)" : ""));
    }
    ++result.sockets;
  }
  result.description = "DDS confined to interface " + result.interface + ": " + std::to_string(result.sockets) +
                       " UDP sockets bound to it (SO_BINDTODEVICE)";
  return result;
}

}  // namespace vifusion::dds
