#include "vifusion/dds/echo.hpp"

#include <array>
#include <limits>
#include <string>
#include <string_view>

#include "message_json.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/dds/reader.hpp"
#include "vifusion/dds/topics.hpp"

namespace vifusion::dds {
namespace {

/// A topic echo can subscribe to, with its type erased.
struct EchoTopic {
  std::string_view name;
  const dds_topic_descriptor_t* descriptor;
  TopicQos qos;
  void (*print)(detail::JsonLine& json, const void* sample, bool full_arrays);
};

template <typename Msg>
EchoTopic echoTopic(const Topic<Msg>& topic) {
  return {topic.name, &msg::Descriptor<Msg>::get(), topic.qos,
          [](detail::JsonLine& json, const void* sample, bool full) {
            detail::writeJson(json, *static_cast<const Msg*>(sample), full);
          }};
}

const std::array<EchoTopic, 8> kEchoTopics = {
    echoTopic(topics::kOdometry),    echoTopic(topics::kPose),
    echoTopic(topics::kTf),          echoTopic(topics::kImuState),
    echoTopic(topics::kMap),         echoTopic(topics::kStatus),
    echoTopic(topics::kDiagnostics), echoTopic(topics::kMapSaveRequest),
};

const EchoTopic* findTopic(std::string_view dds_name) {
  for (const EchoTopic& topic : kEchoTopics) {
    if (topic.name == dds_name) return &topic;
  }
  return nullptr;
}

std::string knownTopics() {
  std::string names;
  for (const EchoTopic& topic : kEchoTopics) {
    if (!names.empty()) names += ", ";
    names += topic.name;
  }
  return names;
}

std::string seconds(std::int64_t t_ns) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g s", nsToSeconds(t_ns));
  return text;
}

int fail(int code, const std::string& message) {
  std::fprintf(stderr, "vifusion echo: %s\n", message.c_str());
  return code;
}

}  // namespace

void EchoOptions::validate() const {
  if (topic.empty()) throw Error("echo option 'topic' is empty");
  if (timeout_ns < 0) throw Error("echo option 'timeout_ns' = " + std::to_string(timeout_ns) + " must be >= 0");
  participant.validate();
}

int echo(const EchoOptions& options, std::FILE* out) {
  try {
    options.validate();
    const std::string name = ddsTopicName(options.topic);
    const EchoTopic* topic = findTopic(name);
    if (topic == nullptr) {
      return fail(kEchoFailed, "unknown topic '" + options.topic + "' (DDS '" + name + "'); known: " + knownTopics());
    }
    Participant participant(options.participant);
    // Same QoS as vifusion's writer: reliable, and transient-local for the map so the last chunk
    // published before echo started arrives too.
    detail::ReaderBase reader(participant, *topic->descriptor, topic->name, topic->qos);

    const std::int64_t start_ns = monotonicNowNs();
    const std::int64_t deadline_ns =
        options.timeout_ns > 0 ? start_ns + options.timeout_ns : std::numeric_limits<std::int64_t>::max();
    std::uint64_t received = 0;
    detail::JsonLine json;
    const auto print = [&](const void* sample) {
      json.clear();
      topic->print(json, sample, options.full_arrays);
      std::fwrite(json.text().data(), 1, json.text().size(), out);
      std::fputc('\n', out);
      std::fflush(out);
    };
    while (options.count == 0 || received < options.count) {
      const std::int64_t now_ns = monotonicNowNs();
      if (now_ns >= deadline_ns) break;
      const std::int64_t wait_ns = options.timeout_ns > 0 ? deadline_ns - now_ns : DDS_INFINITY;
      if (!reader.waitForData(wait_ns)) continue;
      const std::uint64_t wanted = options.count == 0 ? detail::ReaderBase::kTakeBatch : options.count - received;
      const std::uint32_t batch =
          static_cast<std::uint32_t>(wanted < detail::ReaderBase::kTakeBatch ? wanted : detail::ReaderBase::kTakeBatch);
      received += reader.take(print, batch);
    }
    if (options.count > 0 ? received >= options.count : received > 0) return kEchoOk;
    const std::string expected = options.count > 0 ? " of " + std::to_string(options.count) : "";
    return fail(kEchoTimedOut, "received " + std::to_string(received) + expected + " samples on '" + name +
                                   "' within " + seconds(options.timeout_ns) +
                                   " (writers matched: " + std::to_string(reader.matchedWriters()) + ")");
  } catch (const Error& e) {
    return fail(kEchoFailed, e.what());
  }
}

}  // namespace vifusion::dds
