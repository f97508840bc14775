// With ../shared/dds/loopback.xml Cyclone must stay on the loopback interface. The sockets this
// process owns (inodes behind /proc/self/fd) are looked up in /proc/self/net/* to see their local
// addresses, after a writer and a reader exist so every DDSI socket has been made.
//
// What Cyclone 0.10.2 does (ddsi_udp.c, ddsi_udp_create_conn): its TRANSMIT socket is bound to the
// configured interface's address, 127.0.0.1; its unicast RECEIVE sockets are bound to INADDR_ANY
// (0.0.0.0) on the domain's ports whatever the configuration says. Participant therefore binds every
// one of them to the device lo (socket_confinement.hpp), so the kernel delivers to them only what
// arrived on lo: that binding is checked here socket by socket.

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "dds_test_support.hpp"
#include "vifusion/dds/reader.hpp"
#include "vifusion/dds/writer.hpp"

namespace vifusion::dds {
namespace {

/// Inodes of the sockets this process has open.
std::set<std::string> ownSocketInodes() {
  std::set<std::string> inodes;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd")) {
    std::error_code error;
    const std::string target = std::filesystem::read_symlink(entry.path(), error).string();
    if (!error && target.starts_with("socket:[")) inodes.insert(target.substr(8, target.size() - 9));
  }
  return inodes;
}

/// "a.b.c.d:port" of an IPv4 /proc/net entry's "0100007F:1CF0" (address in host byte order).
std::string ipv4Address(const std::string& hex) {
  const unsigned long address = std::stoul(hex.substr(0, 8), nullptr, 16);
  std::ostringstream text;
  text << (address & 0xFF) << '.' << (address >> 8 & 0xFF) << '.' << (address >> 16 & 0xFF) << '.'
       << (address >> 24 & 0xFF) << ':' << std::stoul(hex.substr(9), nullptr, 16);
  return text.str();
}

/// Local addresses, by protocol table ("udp", "tcp6", …), of this process's sockets.
std::map<std::string, std::vector<std::string>> ownSocketAddresses() {
  const std::set<std::string> inodes = ownSocketInodes();
  std::map<std::string, std::vector<std::string>> addresses;
  for (const std::string table : {"udp", "udp6", "tcp", "tcp6", "raw", "raw6", "udplite", "udplite6"}) {
    std::ifstream in("/proc/self/net/" + table);
    std::string line;
    std::getline(in, line);  // column titles
    while (std::getline(in, line)) {
      std::istringstream fields(line);
      std::string slot, local, remote, state, queues, timer, retransmits, uid, timeout, inode;
      fields >> slot >> local >> remote >> state >> queues >> timer >> retransmits >> uid >> timeout >> inode;
      if (inodes.count(inode) == 0) continue;
      addresses[table].push_back(table == "udp" || table == "tcp" ? ipv4Address(local) : local);
    }
  }
  return addresses;
}

/// Cyclone's default port mapping for unicast discovery and data (platform.md §2.4):
/// 7400 + 250·domain + 10 + 2·participant index (+ 1 for data); loopback.xml allows index 0..32.
bool isDomainUnicastPort(std::uint32_t port, std::uint32_t domain_id) {
  const std::uint32_t first = 7400 + 250 * domain_id + 10;
  return port >= first && port <= first + 2 * 32 + 1;
}

TEST(DdsLoopback, SocketsStayOnLoopback) {
  const ParticipantOptions options = test::loopbackOptions();
  const Participant participant(options);
  const Writer writer(participant, topics::kOdometry);
  const Reader reader(participant, topics::kOdometry);

  const auto addresses = ownSocketAddresses();
  for (const auto& [table, list] : addresses) {
    EXPECT_EQ(table, "udp") << "Cyclone opened " << table << " sockets: only UDP over IPv4 on lo is configured";
  }
  ASSERT_EQ(addresses.count("udp"), 1u) << "no UDP socket found: /proc/self/net/udp unreadable?";
  int bound_to_loopback = 0;
  for (const std::string& address : addresses.at("udp")) {
    if (address.starts_with("127.0.0.1:")) {
      ++bound_to_loopback;
    } else {
      // Cyclone 0.10's unicast receive sockets (see the top of this file); nothing else may appear.
      EXPECT_TRUE(address.starts_with("0.0.0.0:")) << address;
      EXPECT_TRUE(isDomainUnicastPort(static_cast<std::uint32_t>(std::stoul(address.substr(address.find(':') + 1))),
                                      options.domain_id))
          << address << " is not a receive port of domain " << options.domain_id;
    }
  }
  EXPECT_GE(bound_to_loopback, 1) << "the transmit socket must be bound to 127.0.0.1";

  const std::set<int> sockets = udpSocketDescriptors();
  EXPECT_EQ(static_cast<int>(sockets.size()), participant.confinement().sockets)
      << participant.confinement().description;
  EXPECT_EQ(participant.confinement().interface, "lo") << participant.confinement().description;
  for (const int fd : sockets) {
    char device[64] = {};
    socklen_t length = sizeof(device);
    ASSERT_EQ(getsockopt(fd, SOL_SOCKET, SO_BINDTODEVICE, device, &length), 0) << "socket " << fd;
    EXPECT_STREQ(device, "lo") << "UDP socket " << fd << " is not bound to the device lo: it would receive from "
                               << "every interface";
  }
}

TEST(DdsLoopback, SocketsOpenedBeforeTheDomainAreLeftAlone) {
  // A UDP socket the application opened itself (before the domain) is not Cyclone's to confine.
  const int own = socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(own, 0);
  {
    const Participant participant(test::loopbackOptions());
    char device[64] = {};
    socklen_t length = sizeof(device);
    ASSERT_EQ(getsockopt(own, SOL_SOCKET, SO_BINDTODEVICE, device, &length), 0);
    EXPECT_STREQ(device, "") << "the application's own socket was bound to " << device;
    EXPECT_GE(participant.confinement().sockets, 2) << participant.confinement().description;
  }
  close(own);
}

}  // namespace
}  // namespace vifusion::dds
