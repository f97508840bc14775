#include "vifusion/recording/open_recorded.hpp"

#include <string_view>

#include "vifusion/core/error.hpp"
#include "vifusion/recording/recording_reader.hpp"

namespace vifusion::recording {
namespace {
constexpr std::string_view kRecordingPrefix = "rec:";
}  // namespace

std::unique_ptr<datasets::DatasetReader> openRecorded(const std::string& spec) {
  if (!spec.starts_with(kRecordingPrefix)) return datasets::openDataset(spec);
  const std::string path = spec.substr(kRecordingPrefix.size());
  if (path.empty()) throw Error("source '" + spec + "': no file after 'rec:'");
  return std::make_unique<RecordingReader>(path);
}

}  // namespace vifusion::recording
