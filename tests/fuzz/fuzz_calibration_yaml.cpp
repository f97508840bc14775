// libFuzzer target: the rig calibration readers on arbitrary text. The first byte chooses the reader:
// calibration.yaml as a file (readCalibrationYaml) or as text embedded in a recording
// (readCalibrationYamlText), or a Kalibr pair (camchain-imucam.yaml and imu.yaml, joined by a NUL byte).
// Besides "a named vifusion::Error or success", a calibration that is accepted must survive our own writer:
// written, read back and written again, the text is the same but for rounding in the last digits.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <sstream>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "vifusion/datasets/kalibr.hpp"

namespace {

using namespace vifusion;
using namespace vifusion::fuzz;

enum class Reader : std::uint8_t { kFile, kText, kKalibr, kCount };

/// Transforms are written as 4×4 matrices of the inverse and read back through a rotation fit, so a round
/// trip may move a value by a few ulp [relative].
constexpr double kRoundTripTolerance = 1e-12;

/// Two words that are the same but for the number in them (YAML's flow sequences wrap numbers in "[", ",", "]"),
/// which agree within kRoundTripTolerance.
bool sameWord(const std::string& a, const std::string& b) {
  if (a == b) return true;
  const std::size_t start = a.find_first_of("+-.0123456789");
  if (start == std::string::npos || start != b.find_first_of("+-.0123456789") ||
      a.compare(0, start, b, 0, start) != 0) {
    return false;
  }
  char *end_a = nullptr, *end_b = nullptr;
  const double x = std::strtod(a.c_str() + start, &end_a), y = std::strtod(b.c_str() + start, &end_b);
  if (end_a == a.c_str() + start || std::string_view(end_a) != std::string_view(end_b)) return false;
  return std::abs(x - y) <= kRoundTripTolerance * std::max({1.0, std::abs(x), std::abs(y)});
}

/// The same words, numbers within kRoundTripTolerance of each other.
bool sameText(const std::string& a, const std::string& b) {
  std::istringstream words_a(a), words_b(b);
  std::string word_a, word_b;
  while (words_a >> word_a) {
    if (!(words_b >> word_b) || !sameWord(word_a, word_b)) return false;
  }
  return !(words_b >> word_b);
}

void requireWriterRoundTrip(const RigCalibration& calibration) {
  const std::string written = datasets::calibrationYamlText(calibration);
  const RigCalibration reread = datasets::readCalibrationYamlText(written, "written.yaml");
  require(sameText(datasets::calibrationYamlText(reread), written));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const ScratchFolder folder;
  if (size == 0) return 0;
  const std::span<const std::uint8_t> input(data + 1, size - 1);
  RigCalibration calibration;
  bool parsed = false;
  switch (static_cast<Reader>(data[0] % static_cast<std::uint8_t>(Reader::kCount))) {
    case Reader::kFile: {
      const auto path = folder.write("calibration.yaml", input);
      parsed = parsedOrNamedError({"calibration.yaml"}, [&] { calibration = datasets::readCalibrationYaml(path); });
      break;
    }
    case Reader::kText:
      parsed = parsedOrNamedError({"recorded.yaml"}, [&] {
        calibration = datasets::readCalibrationYamlText(std::string(asText(input)), "recorded.yaml");
      });
      break;
    case Reader::kKalibr: {
      const auto parts = splitAtNul(input, 2);
      const auto camchain = folder.write("camchain-imucam.yaml", parts[0]);
      const auto imu = folder.write("imu.yaml", parts.size() > 1 ? parts[1] : std::span<const std::uint8_t>());
      parsed = parsedOrNamedError({"camchain-imucam.yaml", "imu.yaml"},
                                  [&] { calibration = datasets::readKalibr(camchain, imu); });
      break;
    }
    case Reader::kCount:
      break;
  }
  if (parsed) requireWriterRoundTrip(calibration);
  return 0;
}
