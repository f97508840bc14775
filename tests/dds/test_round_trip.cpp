// Every published type through a writer and a reader (one participant, so through Cyclone's
// serialiser and deserialiser) comes back field for field, bit for bit.

#include <gtest/gtest.h>

#include "dds_test_support.hpp"
#include "message_equality.hpp"
#include "sample_messages.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/dds/reader.hpp"
#include "vifusion/dds/writer.hpp"

namespace vifusion::dds {
namespace {

constexpr std::int64_t kTimeoutNs = 5 * kNsPerSecond;

template <typename Msg>
void expectRoundTrip(const Participant& participant, const Topic<Msg>& topic, const Msg& sent) {
  SCOPED_TRACE(std::string(topic.name));
  Reader<Msg> reader(participant, topic);
  Writer<Msg> writer(participant, topic);
  ASSERT_TRUE(writer.write(sent));
  ASSERT_TRUE(reader.waitForData(kTimeoutNs));
  std::size_t received = 0;
  reader.take([&](const Msg& message) {
    test::expectSame(message, sent, std::string(topic.name));
    ++received;
  });
  EXPECT_EQ(received, 1u);
}

TEST(DdsRoundTrip, EveryTopicTypeComesBackExactly) {
  const Participant participant(test::loopbackOptions());
  const test::SampleMessages samples;
  expectRoundTrip(participant, topics::kPose, samples.pose);
  expectRoundTrip(participant, topics::kOdometry, samples.odometry);
  expectRoundTrip(participant, topics::kTf, samples.tf);
  expectRoundTrip(participant, topics::kMap, samples.map);
  expectRoundTrip(participant, topics::kDiagnostics, samples.diagnostics);
  expectRoundTrip(participant, topics::kImuState, samples.imu_state);
  expectRoundTrip(participant, topics::kImuState, samples.imu_state_from_variances);
  expectRoundTrip(participant, topics::kOdometry, samples.inertial_odometry);
  expectRoundTrip(participant, topics::kStatus, samples.status);
  expectRoundTrip(participant, topics::kMapSaveRequest, samples.map_save_request);
}

TEST(DdsRoundTrip, KeepsEverySampleInOrderUpToTheDepth) {
  const Participant participant(test::loopbackOptions());
  Reader reader(participant, topics::kStatus);
  Writer writer(participant, topics::kStatus);
  msg::Status status{};
  status.header = makeHeader(0, "vifusion");
  for (std::uint64_t beat = 1; beat <= 5; ++beat) {
    status.heartbeat = beat;
    ASSERT_TRUE(writer.write(status));
  }
  std::vector<std::uint64_t> beats;
  while (beats.size() < 5 && reader.waitForData(kTimeoutNs)) {
    reader.take([&](const msg::Status& s) { beats.push_back(s.heartbeat); });
  }
  EXPECT_EQ(beats, (std::vector<std::uint64_t>{1, 2, 3, 4, 5}));
}

TEST(DdsRoundTrip, OtherPartitionsHearNothing) {
  const Participant participant(test::loopbackOptions());
  Reader same_partition(participant, topics::kPose);
  // A subscriber of the same participant in another partition: only the partition differs.
  dds_qos_t* qos = dds_create_qos();
  dds_qset_partition1(qos, "vifusion_test_other_partition");
  const Entity subscriber(dds_create_subscriber(participant.participant(), qos, nullptr));
  dds_delete_qos(qos);
  ASSERT_GT(subscriber.get(), 0);
  const Entity other_partition(dds_create_reader(subscriber.get(), same_partition.topic(), nullptr, nullptr));
  ASSERT_GT(other_partition.get(), 0);

  Writer writer(participant, topics::kPose);
  const test::SampleMessages samples;
  ASSERT_TRUE(writer.write(samples.pose));
  ASSERT_TRUE(same_partition.waitForData(kTimeoutNs));
  void* sample = nullptr;
  dds_sample_info_t info;
  EXPECT_EQ(dds_take(other_partition.get(), &sample, &info, 1, 1), 0);
}

}  // namespace
}  // namespace vifusion::dds
