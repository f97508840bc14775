// The groups that permission errors tell people to join are the ones systemd/99-vifusion.rules really gives.

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <utility>

#include "vifusion/discovery/zr300_usb.hpp"

namespace vifusion::discovery::test {
namespace {

std::string productText(std::uint16_t product) {
  char text[8];
  std::snprintf(text, sizeof(text), "%04x", product);
  return text;
}

TEST(UdevRules, PermissionErrorsNameTheGroupsTheRulesGive) {
  const std::string path = std::string(VIFUSION_SYSTEMD_DIR) + "/" + std::string(kUdevRulesFile);
  std::ifstream rules(path);
  ASSERT_TRUE(rules) << "cannot read " << path;

  // (subsystem, product) → (group, mode), from every rule that matches vendor 8086.
  const std::regex rule(
      R"re(^SUBSYSTEM=="([a-z0-9_]+)".*ATTRS?\{idVendor\}=="8086".*ATTRS?\{idProduct\}=="([0-9a-f]{4})".*)re"
      R"re(GROUP="([a-z]+)", MODE="([0-7]{4})")re");
  std::map<std::pair<std::string, std::string>, std::pair<std::string, std::string>> granted;
  std::string line;
  while (std::getline(rules, line)) {
    std::smatch match;
    if (std::regex_search(line, match, rule)) granted[{match[1], match[2]}] = {match[3], match[4]};
  }

  const std::string camera = productText(kCameraProductId);
  const std::string adapter = productText(kAdapterProductId);
  ASSERT_EQ(granted.size(), 4u);
  for (const std::string& product : {camera, adapter}) {
    const auto video = granted[std::make_pair("video4linux", product)];
    const auto usb = granted[std::make_pair("usb", product)];
    EXPECT_EQ(video.first, kVideoNodeGroup) << product;
    EXPECT_EQ(usb.first, kUsbNodeGroup) << product;
    EXPECT_EQ(video.second, "0660") << product;
    EXPECT_EQ(usb.second, "0660") << product;
  }
}

}  // namespace
}  // namespace vifusion::discovery::test
