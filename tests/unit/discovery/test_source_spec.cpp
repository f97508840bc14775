// "zr300" and "zr300:SERIAL" source specs, and what a serial matches. No test bed needed.

#include <gtest/gtest.h>

#include <string>

#include "discovery_fixture.hpp"
#include "vifusion/discovery/source_spec.hpp"

namespace vifusion::discovery::test {
namespace {

TEST(SourceSpec, ParsesTheTwoForms) {
  const auto any = parseZr300SourceSpec("zr300");
  ASSERT_TRUE(any.has_value());
  EXPECT_EQ(any->serial, "");
  const auto named = parseZr300SourceSpec("zr300:SN_4071801153");
  ASSERT_TRUE(named.has_value());
  EXPECT_EQ(named->serial, "SN_4071801153");
}

TEST(SourceSpec, LeavesOtherSourcesToTheirReaders) {
  for (const char* other : {"", "sim:living_room_0", "tum:/data/fr1_desk", "zr3000", "zr300x", "ZR300", "zr30"}) {
    EXPECT_FALSE(parseZr300SourceSpec(other).has_value()) << other;
  }
}

TEST(SourceSpec, RejectsAnEmptySerial) {
  expectProblem([] { parseZr300SourceSpec("zr300:"); }, DiscoveryProblem::kBadSpec,
                "source 'zr300:': the serial after 'zr300:' is empty; use zr300 or zr300:SERIAL");
}

TEST(SourceSpec, RejectsCharactersNoUsbSerialHas) {
  expectProblem([] { parseZr300SourceSpec("zr300:SN 407"); }, DiscoveryProblem::kBadSpec,
                "character 3 of the serial is not printable ASCII, or is a space or ':'");
  expectProblem([] { parseZr300SourceSpec("zr300:SN_1:2"); }, DiscoveryProblem::kBadSpec, "character 5 ");
  expectProblem([] { parseZr300SourceSpec("zr300:SN\t1"); }, DiscoveryProblem::kBadSpec, "character 3 ");
  expectProblem([] { parseZr300SourceSpec("zr300:SN\xc3\xa9"); }, DiscoveryProblem::kBadSpec, "character 3 ");
}

TEST(SourceSpec, AcceptsSerialsUpToTheUsbStringLimit) {
  const std::string longest(kMaxSerialLength, '7');
  const auto spec = parseZr300SourceSpec("zr300:" + longest);
  ASSERT_TRUE(spec.has_value());
  EXPECT_EQ(spec->serial.size(), 126u);
  expectProblem([&] { parseZr300SourceSpec("zr300:" + longest + "7"); }, DiscoveryProblem::kBadSpec,
                "the serial has 127 characters, a USB serial at most 126");
}

TEST(SourceSpec, SerialMatchesWithOrWithoutTheFirmwarePrefix) {
  EXPECT_TRUE(serialMatches("SN_4071801153", "SN_4071801153"));
  EXPECT_TRUE(serialMatches("4071801153", "SN_4071801153"));
  EXPECT_FALSE(serialMatches("071801153", "SN_4071801153"));  // a suffix is not the serial
  EXPECT_FALSE(serialMatches("SN_4071801153", "4071801153"));
  EXPECT_FALSE(serialMatches("SN_4071801153", "SN_3511803652"));
  EXPECT_FALSE(serialMatches("", ""));  // no serial named: selection takes the only camera instead
  EXPECT_FALSE(serialMatches("", "SN_4071801153"));
}

}  // namespace
}  // namespace vifusion::discovery::test
