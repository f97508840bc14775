#include "vifusion/discovery/source_spec.hpp"

#include <algorithm>

#include "vifusion/discovery/discovery_error.hpp"

namespace vifusion::discovery {
namespace {

constexpr char kSchemeSeparator = ':';
// Printable ASCII without the space: what USB serials are in practice, and safe to echo in messages.
constexpr char kFirstSerialChar = '!';
constexpr char kLastSerialChar = '~';

bool isSerialChar(char c) { return c >= kFirstSerialChar && c <= kLastSerialChar && c != kSchemeSeparator; }

}  // namespace

std::optional<Zr300SourceSpec> parseZr300SourceSpec(std::string_view text) {
  if (text == kSourceScheme) return Zr300SourceSpec{};
  if (!text.starts_with(kSourceScheme) || text.size() == kSourceScheme.size() ||
      text[kSourceScheme.size()] != kSchemeSeparator) {
    return std::nullopt;
  }
  const std::string_view serial = text.substr(kSourceScheme.size() + 1);
  const std::string spec(text);
  if (serial.empty()) {
    throw DiscoveryError(DiscoveryProblem::kBadSpec,
                         "source '" + spec + "': the serial after 'zr300:' is empty; use zr300 or zr300:SERIAL");
  }
  if (serial.size() > kMaxSerialLength) {
    throw DiscoveryError(DiscoveryProblem::kBadSpec,
                         "source '" + spec + "': the serial has " + std::to_string(serial.size()) +
                             " characters, a USB serial at most " + std::to_string(kMaxSerialLength));
  }
  const auto bad = std::find_if_not(serial.begin(), serial.end(), isSerialChar);
  if (bad != serial.end()) {
    // The spec is not echoed: the offending character may be a control character.
    throw DiscoveryError(DiscoveryProblem::kBadSpec, "source zr300:SERIAL: character " +
                                                         std::to_string(bad - serial.begin() + 1) +
                                                         " of the serial is not printable ASCII, or is a space or ':'");
  }
  return Zr300SourceSpec{std::string(serial)};
}

bool serialMatches(std::string_view wanted, std::string_view usb_serial) {
  if (wanted.empty()) return false;
  if (wanted == usb_serial) return true;
  return usb_serial.starts_with(kUsbSerialPrefix) && usb_serial.substr(kUsbSerialPrefix.size()) == wanted;
}

}  // namespace vifusion::discovery
