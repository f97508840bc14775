// Names ROS 2 relies on (topic "rt/…", type "pkg::msg::dds_::Type_"), the topics' QoS as Cyclone
// applies it, and the participant options' validation.

#include <gtest/gtest.h>

#include <string>

#include "dds_test_support.hpp"
#include "vifusion/dds/reader.hpp"
#include "vifusion/dds/writer.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::dds {
namespace {

template <typename Msg>
std::string typeNameOnTheWire(const Participant& participant, const Topic<Msg>& topic) {
  const Writer<Msg> writer(participant, topic);
  char name[128] = {};
  EXPECT_GT(dds_get_type_name(writer.topic(), name, sizeof(name)), 0);  // the name's length
  return name;
}

TEST(DdsTopics, TypeNamesFollowRmwCyclonedds) {
  const Participant participant(test::loopbackOptions());
  EXPECT_EQ(typeNameOnTheWire(participant, topics::kOdometry), "nav_msgs::msg::dds_::Odometry_");
  EXPECT_EQ(typeNameOnTheWire(participant, topics::kPose), "geometry_msgs::msg::dds_::PoseStamped_");
  EXPECT_EQ(typeNameOnTheWire(participant, topics::kTf), "tf2_msgs::msg::dds_::TFMessage_");
  EXPECT_EQ(typeNameOnTheWire(participant, topics::kImuState), "vifusion_msgs::msg::dds_::ImuState_");
  EXPECT_EQ(typeNameOnTheWire(participant, topics::kMap), "sensor_msgs::msg::dds_::PointCloud2_");
  EXPECT_EQ(typeNameOnTheWire(participant, topics::kStatus), "vifusion_msgs::msg::dds_::Status_");
  EXPECT_EQ(typeNameOnTheWire(participant, topics::kMapSaveRequest), "vifusion_msgs::msg::dds_::MapSaveRequest_");
  EXPECT_EQ(typeNameOnTheWire(participant, topics::kDiagnostics), "diagnostic_msgs::msg::dds_::DiagnosticArray_");
}

TEST(DdsTopics, NestedTypesFollowRmwCyclonedds) {
  EXPECT_STREQ(builtin_interfaces_msg_dds__Time__desc.m_typename, "builtin_interfaces::msg::dds_::Time_");
  EXPECT_STREQ(std_msgs_msg_dds__Header__desc.m_typename, "std_msgs::msg::dds_::Header_");
  EXPECT_STREQ(geometry_msgs_msg_dds__TransformStamped__desc.m_typename, "geometry_msgs::msg::dds_::TransformStamped_");
  EXPECT_STREQ(sensor_msgs_msg_dds__PointField__desc.m_typename, "sensor_msgs::msg::dds_::PointField_");
  EXPECT_STREQ(diagnostic_msgs_msg_dds__KeyValue__desc.m_typename, "diagnostic_msgs::msg::dds_::KeyValue_");
}

TEST(DdsTopics, KeylessAsRos2) {
  // rmw_cyclonedds creates its types without keys: one instance per topic.
  EXPECT_EQ(msg::Descriptor<msg::Odometry>::get().m_nkeys, 0u);
  EXPECT_EQ(msg::Descriptor<msg::PoseStamped>::get().m_nkeys, 0u);
  EXPECT_EQ(msg::Descriptor<msg::TFMessage>::get().m_nkeys, 0u);
  EXPECT_EQ(msg::Descriptor<msg::PointCloud2>::get().m_nkeys, 0u);
  EXPECT_EQ(msg::Descriptor<msg::DiagnosticArray>::get().m_nkeys, 0u);
  EXPECT_EQ(msg::Descriptor<msg::ImuState>::get().m_nkeys, 0u);
  EXPECT_EQ(msg::Descriptor<msg::Status>::get().m_nkeys, 0u);
}

TEST(DdsTopics, TopicNamesCarryTheRtPrefix) {
  EXPECT_EQ(topics::kOdometry.name, "rt/vifusion/odometry");
  EXPECT_EQ(topics::kPose.name, "rt/vifusion/pose");
  EXPECT_EQ(topics::kTf.name, "rt/tf");
  EXPECT_EQ(topics::kImuState.name, "rt/vifusion/imu_state");
  EXPECT_EQ(topics::kMap.name, "rt/vifusion/map");
  EXPECT_EQ(topics::kStatus.name, "rt/vifusion/status");
  EXPECT_EQ(topics::kDiagnostics.name, "rt/diagnostics");
}

TEST(DdsTopics, RosNamesMapToDdsNames) {
  EXPECT_EQ(ddsTopicName("/vifusion/odometry"), "rt/vifusion/odometry");
  EXPECT_EQ(ddsTopicName("vifusion/odometry"), "rt/vifusion/odometry");
  EXPECT_EQ(ddsTopicName("rt/vifusion/odometry"), "rt/vifusion/odometry");
  EXPECT_EQ(ddsTopicName("/tf"), "rt/tf");
  vifusion::test::expectError([] { ddsTopicName(""); }, "names no topic");
  vifusion::test::expectError([] { ddsTopicName("/"); }, "names no topic");
  vifusion::test::expectError([] { ddsTopicName("rt/"); }, "names no topic");
}

// The QoS Cyclone actually gives the endpoints, read back from the entities.
struct EndpointQos {
  dds_reliability_kind_t reliability{};
  dds_history_kind_t history{};
  std::int32_t depth = 0;
  dds_durability_kind_t durability{};
  std::vector<dds_data_representation_id_t> representations;
};

EndpointQos qosOf(dds_entity_t entity) {
  dds_qos_t* qos = dds_create_qos();
  EXPECT_EQ(dds_get_qos(entity, qos), DDS_RETCODE_OK);
  EndpointQos result;
  dds_duration_t blocking = 0;
  EXPECT_TRUE(dds_qget_reliability(qos, &result.reliability, &blocking));
  EXPECT_TRUE(dds_qget_history(qos, &result.history, &result.depth));
  EXPECT_TRUE(dds_qget_durability(qos, &result.durability));
  std::uint32_t n = 0;
  dds_data_representation_id_t* ids = nullptr;
  EXPECT_TRUE(dds_qget_data_representation(qos, &n, &ids));
  result.representations.assign(ids, ids + n);
  dds_free(ids);
  dds_delete_qos(qos);
  return result;
}

TEST(DdsTopics, QosReliableKeepLastXcdr1) {
  const Participant participant(test::loopbackOptions());
  const Writer odometry(participant, topics::kOdometry);
  const Writer tf(participant, topics::kTf);
  const Writer map(participant, topics::kMap);
  const Reader map_reader(participant, topics::kMap);

  const EndpointQos volatile_qos = qosOf(odometry.writer());
  EXPECT_EQ(volatile_qos.reliability, DDS_RELIABILITY_RELIABLE);
  EXPECT_EQ(volatile_qos.history, DDS_HISTORY_KEEP_LAST);
  EXPECT_EQ(volatile_qos.depth, 10);
  EXPECT_EQ(volatile_qos.durability, DDS_DURABILITY_VOLATILE);
  EXPECT_EQ(volatile_qos.representations, std::vector<dds_data_representation_id_t>{DDS_DATA_REPRESENTATION_XCDR1});
  EXPECT_EQ(qosOf(tf.writer()).depth, 100);

  for (const dds_entity_t entity : {map.writer(), map_reader.reader()}) {
    const EndpointQos latched = qosOf(entity);
    EXPECT_EQ(latched.reliability, DDS_RELIABILITY_RELIABLE);
    EXPECT_EQ(latched.depth, 1);
    EXPECT_EQ(latched.durability, DDS_DURABILITY_TRANSIENT_LOCAL);
    EXPECT_EQ(latched.representations, std::vector<dds_data_representation_id_t>{DDS_DATA_REPRESENTATION_XCDR1});
  }
}

TEST(DdsParticipant, OptionsValidation) {
  ParticipantOptions options = test::loopbackOptions();
  EXPECT_NO_THROW(options.validate());
  options.domain_id = 233;
  vifusion::test::expectError([&] { options.validate(); }, "'domain_id' = 233");
  options = test::loopbackOptions();
  options.config.clear();
  vifusion::test::expectError([&] { options.validate(); }, "'config' is empty");
  options.config = "/nonexistent/cyclonedds.xml";
  vifusion::test::expectError([&] { options.validate(); },
                              "no Cyclone configuration file '/nonexistent/cyclonedds.xml'");
  options.config = "file:///nonexistent/cyclonedds.xml";
  vifusion::test::expectError([&] { options.validate(); },
                              "no Cyclone configuration file '/nonexistent/cyclonedds.xml'");
  options = test::loopbackOptions();
  options.partition = "vifusion*";
  vifusion::test::expectError([&] { options.validate(); }, "'partition'");
}

TEST(DdsParticipant, ConfigAsFileUriOrInlineXml) {
  ParticipantOptions options = test::loopbackOptions();
  options.config = std::string("file://") + VIFUSION_DDS_LOOPBACK_CONFIG;
  EXPECT_NO_THROW(Participant{options});
  options.config =
      "<CycloneDDS><Domain id=\"any\"><General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
      "<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex>"
      "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery></Domain></CycloneDDS>";
  EXPECT_NO_THROW(Participant{options});
}

TEST(DdsParticipant, OnePerDomainAndProcess) {
  const ParticipantOptions options = test::loopbackOptions();
  const Participant first(options);
  vifusion::test::expectError([&] { Participant second(options); }, "already exists in this process");
}

TEST(DdsParticipant, CycloneRejectsABadConfiguration) {
  ParticipantOptions options = test::loopbackOptions();
  options.config = "<CycloneDDS><Domain><General><NoSuchSetting>1</NoSuchSetting></General></Domain></CycloneDDS>";
  vifusion::test::expectError([&] { Participant participant(options); }, "inline XML configuration");
}

}  // namespace
}  // namespace vifusion::dds
