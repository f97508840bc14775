#pragma once
// The live camera as a source spec (DESIGN.md §5): "zr300" takes the one camera present, "zr300:SERIAL"
// the camera with that serial.
//
// A serial is the DS4's iSerialNumber as sysfs shows it, "SN_4071801153" on real units; the digits alone
// ("4071801153") match too, so both what `lsusb -v` and what `vifusion` print can be typed.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace vifusion::discovery {

inline constexpr std::string_view kSourceScheme = "zr300";
/// The prefix the DS4 firmware puts before the digits of its USB serial.
inline constexpr std::string_view kUsbSerialPrefix = "SN_";
/// A USB string descriptor holds at most 126 UTF-16 code units; nothing longer can be a serial.
inline constexpr std::size_t kMaxSerialLength = 126;

struct Zr300SourceSpec {
  std::string serial;  ///< empty: exactly one camera must be present
};

/// "zr300" or "zr300:SERIAL" → the spec; any other text (another source kind, e.g. "tum:DIR") → nullopt.
/// @throws DiscoveryError(kBadSpec) for "zr300:" followed by an empty serial, one longer than
///         kMaxSerialLength, or one with a character other than printable ASCII (space and ':' excluded).
std::optional<Zr300SourceSpec> parseZr300SourceSpec(std::string_view text);

/// Whether a camera whose USB serial is `usb_serial` is the one `wanted` names: equal, or equal to
/// usb_serial without kUsbSerialPrefix. An empty `wanted` matches nothing.
bool serialMatches(std::string_view wanted, std::string_view usb_serial);

}  // namespace vifusion::discovery
