#pragma once
// A typed DDS reader on one of vifusion's topics (topics.hpp): wait for data, then take samples on
// loan from Cyclone (no copy, no allocation of ours) and visit them.

#include <cstddef>
#include <cstdint>
#include <string>

#include "vifusion/dds/entity.hpp"
#include "vifusion/dds/participant.hpp"
#include "vifusion/dds/topics.hpp"

namespace vifusion::dds {
namespace detail {

/// The type-independent part of Reader<Msg>; echo uses it directly with a type chosen at run time.
class ReaderBase {
 public:
  /// Samples taken per call at most.
  static constexpr std::uint32_t kTakeBatch = 16;

  ReaderBase(const Participant& participant, const dds_topic_descriptor_t& descriptor, std::string_view name,
             const TopicQos& qos);

  /// Blocks until a sample can be taken or `timeout_ns` [ns] passed (DDS_INFINITY: no limit).
  /// Returns true when a sample can be taken.
  bool waitForData(std::int64_t timeout_ns) const;
  /// Takes up to min(max_samples, kTakeBatch) samples on loan and calls visit(const void* sample)
  /// for each one that carries data; returns how many were visited. The samples are valid only
  /// during the call.
  template <typename Visit>
  std::size_t take(Visit&& visit, std::uint32_t max_samples = kTakeBatch);
  /// Writers currently matched, remote and local.
  std::uint32_t matchedWriters() const;
  dds_entity_t topic() const { return topic_.get(); }
  dds_entity_t reader() const { return reader_.get(); }

 private:
  /// Returns the loaned samples of one take even if a visitor throws.
  struct Loan {
    dds_entity_t reader;
    void** samples;
    std::int32_t count;
    ~Loan() {
      if (count > 0) static_cast<void>(dds_return_loan(reader, samples, count));
    }
  };

  std::string name_;
  Entity topic_;  // deleted after the reader and waitset that use it
  Entity reader_;
  Entity waitset_;
};

template <typename Visit>
std::size_t ReaderBase::take(Visit&& visit, std::uint32_t max_samples) {
  const std::uint32_t n = max_samples < kTakeBatch ? max_samples : kTakeBatch;
  void* samples[kTakeBatch] = {};
  dds_sample_info_t infos[kTakeBatch];
  const dds_return_t taken = dds_take(reader_.get(), samples, infos, n, n);
  if (taken < 0) checkReturn(taken, "DDS take on '" + name_ + "'");
  const Loan loan{reader_.get(), samples, taken};
  std::size_t visited = 0;
  for (std::int32_t i = 0; i < taken; ++i) {
    // Samples without data only announce that a writer went away.
    if (!infos[i].valid_data) continue;
    visit(static_cast<const void*>(samples[i]));
    ++visited;
  }
  return visited;
}

}  // namespace detail

template <typename Msg>
class Reader {
 public:
  Reader(const Participant& participant, const Topic<Msg>& topic)
      : base_(participant, msg::Descriptor<Msg>::get(), topic.name, topic.qos) {}

  bool waitForData(std::int64_t timeout_ns) const { return base_.waitForData(timeout_ns); }
  /// Calls visit(const Msg&) for up to `max_samples` taken samples; see detail::ReaderBase::take.
  template <typename Visit>
  std::size_t take(Visit&& visit, std::uint32_t max_samples = detail::ReaderBase::kTakeBatch) {
    return base_.take([&visit](const void* sample) { visit(*static_cast<const Msg*>(sample)); }, max_samples);
  }
  std::uint32_t matchedWriters() const { return base_.matchedWriters(); }
  dds_entity_t topic() const { return base_.topic(); }
  dds_entity_t reader() const { return base_.reader(); }

 private:
  detail::ReaderBase base_;
};

}  // namespace vifusion::dds
