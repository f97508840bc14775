// rt/vifusion/map is TRANSIENT_LOCAL with depth 1: a reader that joins after the writer published
// still receives the last map chunk, and only that one.

#include <gtest/gtest.h>

#include <vector>

#include "dds_test_support.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/dds/conversions.hpp"
#include "vifusion/dds/reader.hpp"
#include "vifusion/dds/writer.hpp"

namespace vifusion::dds {
namespace {

constexpr std::int64_t kTimeoutNs = 5 * kNsPerSecond;

TEST(DdsTransientLocal, LateReaderGetsTheLastMapChunk) {
  const Participant participant(test::loopbackOptions());
  Writer writer(participant, topics::kMap);
  const std::vector<MapPoint> first(3);
  std::vector<MapPoint> last(7);
  last[6].confidence = 42.0f;
  ASSERT_TRUE(writer.write(makePointCloud2(1, "world", first)));
  ASSERT_TRUE(writer.write(makePointCloud2(2, "world", last)));

  Reader late(participant, topics::kMap);  // created after both writes
  ASSERT_TRUE(late.waitForData(kTimeoutNs));
  std::vector<std::uint32_t> widths;
  float confidence = 0;
  late.take([&](const msg::PointCloud2& cloud) {
    widths.push_back(cloud.width);
    std::memcpy(&confidence, cloud.data._buffer + 6 * sizeof(MapPoint) + offsetof(MapPoint, confidence), 4);
  });
  EXPECT_EQ(widths, std::vector<std::uint32_t>{7});
  EXPECT_EQ(confidence, 42.0f);
}

TEST(DdsTransientLocal, VolatileTopicsKeepNothingForLateReaders) {
  const Participant participant(test::loopbackOptions());
  Writer writer(participant, topics::kStatus);
  msg::Status status{};
  status.header = makeHeader(0, "vifusion");
  ASSERT_TRUE(writer.write(status));
  Reader late(participant, topics::kStatus);
  EXPECT_FALSE(late.waitForData(200 * kNsPerMillisecond));
}

}  // namespace
}  // namespace vifusion::dds
