#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string_view>

#include "vifusion/core/error.hpp"
#include "vifusion/datasets/fault_injection.hpp"

namespace vifusion::datasets {
namespace {

/// What a fault's VALUE means, and its default when the plan gives none.
enum class ValueUse { kNone, kSeconds, kSignedSecondsRequired, kFrameCount };

struct FaultName {
  FaultKind kind;
  std::string_view name;
  ValueUse value;
  double default_value;
};

// Defaults: a 0.1 s IMU hole is 8 × the largest spacing the IMU checks allow at 200 Hz (2.5 periods), so it is
// always a gap; 0.1 s back is three frame periods at 30 Hz, so the frame is before its predecessor; a 2 s stall is
// longer than a frame period by far yet short enough for a test.
constexpr std::array<FaultName, 12> kFaultNames = {{
    {FaultKind::kImuGap, "imu-gap", ValueUse::kSeconds, 0.1},
    {FaultKind::kImuDuplicate, "imu-duplicate", ValueUse::kNone, 0.0},
    {FaultKind::kImuReorder, "imu-reorder", ValueUse::kNone, 0.0},
    {FaultKind::kImuNan, "imu-nan", ValueUse::kNone, 0.0},
    {FaultKind::kImuInf, "imu-inf", ValueUse::kNone, 0.0},
    {FaultKind::kFrameDrop, "frame-drop", ValueUse::kFrameCount, 1.0},
    {FaultKind::kFrameDuplicate, "frame-duplicate", ValueUse::kNone, 0.0},
    {FaultKind::kFrameBlank, "frame-blank", ValueUse::kFrameCount, 1.0},
    {FaultKind::kTimeBackwards, "time-backwards", ValueUse::kSeconds, 0.1},
    {FaultKind::kClockJump, "clock-jump", ValueUse::kSignedSecondsRequired, 0.0},
    {FaultKind::kStall, "stall", ValueUse::kSeconds, 2.0},
    {FaultKind::kDeviceLost, "device-lost", ValueUse::kNone, 0.0},
}};

/// Longest stall or time shift a plan may ask for [s]: an hour, far beyond any fault worth replaying.
constexpr double kMaxSeconds = 3600.0;
/// Most frames one frame-drop may remove or one frame-blank may blank.
constexpr double kMaxFrameCount = 1e6;

const FaultName& nameOf(FaultKind kind) {
  for (const FaultName& entry : kFaultNames)
    if (entry.kind == kind) return entry;
  throw Error("fault kind without a name");  // unreachable: every kind is in the table
}

std::string knownFaults() {
  std::string list;
  for (const FaultName& entry : kFaultNames) {
    if (!list.empty()) list += ", ";
    list.append(entry.name);
  }
  return list;
}

double parseValue(std::string_view text, const FaultName& fault, const std::string& prefix) {
  const std::string copy(text);
  char* end = nullptr;
  const double value = std::strtod(copy.c_str(), &end);
  if (copy.empty() || end != copy.c_str() + copy.size() || !std::isfinite(value)) {
    throw Error(prefix + "'" + copy + "' is not a number");
  }
  switch (fault.value) {
    case ValueUse::kFrameCount:
      if (value < 1.0 || value > kMaxFrameCount || value != std::floor(value))
        throw Error(prefix + "the frame count must be a whole number from 1 to 1000000, not '" + copy + "'");
      break;
    case ValueUse::kSignedSecondsRequired:
      if (copy.front() != '+' && copy.front() != '-')
        throw Error(prefix + "give the jump's direction with its sign (+1 or -1 s), not '" + copy + "'");
      if (value == 0.0 || std::fabs(value) > kMaxSeconds)
        throw Error(prefix + "the jump must be non-zero and at most an hour, not '" + copy + "' s");
      break;
    case ValueUse::kSeconds:
      if (value <= 0.0 || value > kMaxSeconds)
        throw Error(prefix + "the duration must be above 0 and at most 3600 s, not '" + copy + "'");
      break;
    case ValueUse::kNone:
      break;
  }
  return value;
}

Fault parseFault(std::string_view entry, const std::string& where) {
  const std::string prefix = where + ": '" + std::string(entry) + "': ";
  const std::size_t at = entry.find('@');
  if (at == std::string_view::npos) throw Error(prefix + "expected NAME@FRAME[:VALUE]");
  const std::string_view name = entry.substr(0, at);
  const FaultName* known = nullptr;
  for (const FaultName& candidate : kFaultNames)
    if (candidate.name == name) known = &candidate;
  if (known == nullptr) throw Error(prefix + "unknown fault, the faults are " + knownFaults());
  std::string_view rest = entry.substr(at + 1);
  const std::size_t colon = rest.find(':');
  const std::string_view frame_text = rest.substr(0, colon);
  std::size_t frame = 0;
  const auto [end, ec] = std::from_chars(frame_text.data(), frame_text.data() + frame_text.size(), frame);
  if (frame_text.empty() || ec != std::errc() || end != frame_text.data() + frame_text.size()) {
    throw Error(prefix + "the frame '" + std::string(frame_text) + "' is not a frame index (0, 1, 2, ...)");
  }
  Fault fault;
  fault.kind = known->kind;
  fault.frame = frame;
  fault.value = known->default_value;
  if (colon == std::string_view::npos) {
    if (known->value == ValueUse::kSignedSecondsRequired)
      throw Error(prefix + "a clock jump needs its size, e.g. clock-jump@" + std::string(frame_text) + ":+1");
  } else {
    if (known->value == ValueUse::kNone) throw Error(prefix + std::string(name) + " takes no value");
    fault.value = parseValue(rest.substr(colon + 1), *known, prefix);
  }
  if (fault.frame == 0 && happensBetweenFrames(fault.kind)) {
    throw Error(prefix + "it happens between frames K-1 and K, so K must be at least 1");
  }
  return fault;
}

}  // namespace

std::optional<std::size_t> FaultPlan::deviceLostFrame() const {
  std::optional<std::size_t> first;
  for (const Fault& fault : faults)
    if (fault.kind == FaultKind::kDeviceLost && (!first || fault.frame < *first)) first = fault.frame;
  return first;
}

std::string FaultPlan::describe() const {
  std::string text;
  for (const Fault& fault : faults) {
    const FaultName& name = nameOf(fault.kind);
    if (!text.empty()) text += ',';
    text.append(name.name);
    text += '@';
    text += std::to_string(fault.frame);
    char value[32] = "";
    if (name.value == ValueUse::kSeconds || name.value == ValueUse::kFrameCount) {
      std::snprintf(value, sizeof value, ":%g", fault.value);
    } else if (name.value == ValueUse::kSignedSecondsRequired) {
      std::snprintf(value, sizeof value, ":%+g", fault.value);
    }
    text += value;
  }
  return text;
}

FaultPlan parseFaultPlan(const std::string& spec, const std::string& where) {
  FaultPlan plan;
  std::string_view rest = spec;
  while (!rest.empty()) {
    const std::size_t comma = rest.find(',');
    const std::string_view entry = rest.substr(0, comma);
    if (entry.empty()) throw Error(where + ": an empty entry in '" + spec + "'");
    plan.faults.push_back(parseFault(entry, where));
    if (comma == std::string_view::npos) break;
    rest = rest.substr(comma + 1);
    if (rest.empty()) throw Error(where + ": '" + spec + "' ends with a comma");
  }
  return plan;
}

}  // namespace vifusion::datasets
