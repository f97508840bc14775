// libFuzzer target: the text files of every dataset layout on arbitrary text. The first byte chooses the
// layout; the rest is its files joined by NUL bytes, written into a scratch folder that also holds one empty
// image file per folder a list may name (the lists are read, not the images: fuzz_image_files decodes those):
//   tum      rgb.txt, depth.txt, groundtruth.txt, accelerometer.txt
//   icl      associations.txt, living.gt.freiburg
//   7scenes  frame-000000.pose.txt, camera-intrinsics.txt (beside frame-000000.{color,depth}.png)
//   dataset  calibration.yaml, rgb.txt, depth.txt, imu.csv, groundtruth.txt, groundtruth_states.csv
//   imu.csv (EuRoC), groundtruth_states.csv, a TUM trajectory (eval), states.csv (eval) alone.
// A folder is opened as `vifusion run --source LAYOUT:DIR` opens it; errors must name a file of the layout or
// the folder. An accepted EuRoC IMU file or ground-truth state file must read back bit-exact from our writer.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_support.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/datasets/euroc_imu.hpp"
#include "vifusion/datasets/ground_truth_states.hpp"
#include "vifusion/eval/state_csv.hpp"
#include "vifusion/eval/trajectory_io.hpp"

namespace {

using namespace vifusion;
using namespace vifusion::fuzz;

struct Layout {
  const char* source_prefix;  ///< "tum", … for openDataset; nullptr for a single file
  std::vector<const char*> files;
};

enum class Choice : std::uint8_t {
  kTum,
  kIcl,
  kSevenScenes,
  kDataset,
  kEuroc,
  kStates,
  kTrajectory,
  kEstimated,
  kCount
};

const std::array<Layout, static_cast<std::size_t>(Choice::kCount)> kLayouts = {{
    {"tum", {"rgb.txt", "depth.txt", "groundtruth.txt", "accelerometer.txt"}},
    {"icl", {"associations.txt", "living.gt.freiburg"}},
    {"7scenes", {"frame-000000.pose.txt", "camera-intrinsics.txt"}},
    {"dataset", {"calibration.yaml", "rgb.txt", "depth.txt", "imu.csv", "groundtruth.txt", "groundtruth_states.csv"}},
    {nullptr, {"imu.csv"}},
    {nullptr, {"groundtruth_states.csv"}},
    {nullptr, {"trajectory.txt"}},
    {nullptr, {"states.csv"}},
}};

/// Image files the seed lists name (tests/fuzz/seeds): present, empty, never decoded here.
constexpr std::array<const char*, 4> kImageFiles = {"rgb/1.png", "depth/1.png", "frame-000000.color.png",
                                                    "frame-000000.depth.png"};

bool sameSamples(const std::vector<ImuSample>& a, const std::vector<ImuSample>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].t_ns != b[i].t_ns || a[i].gyro_rad_s != b[i].gyro_rad_s || a[i].accel_mps2 != b[i].accel_mps2)
      return false;
  }
  return true;
}

void readFolder(const ScratchFolder& folder, const Layout& layout) {
  for (const char* image : kImageFiles) {
    std::filesystem::create_directories((folder.path() / image).parent_path());
    folder.write(image, {});
  }
  const std::string dir = folder.path().string();
  std::vector<std::string_view> names(layout.files.begin(), layout.files.end());
  names.push_back(dir);
  try {
    const auto reader = datasets::openDataset(std::string(layout.source_prefix) + ":" + dir);
    require(reader->frameCount() > 0 && !reader->describe().empty());
  } catch (const Error& error) {
    const std::string_view message = error.what();
    bool named = false;
    for (const std::string_view name : names) named = named || message.find(name) != std::string_view::npos;
    require(named);
  }
}

void readFile(const ScratchFolder& folder, Choice choice, std::span<const std::uint8_t> bytes) {
  const char* name = kLayouts[static_cast<std::size_t>(choice)].files.front();
  const auto path = folder.write(name, bytes);
  switch (choice) {
    case Choice::kEuroc: {
      std::vector<ImuSample> samples;
      if (!parsedOrNamedError({name}, [&] { samples = datasets::readEurocImu(path); })) return;
      datasets::writeEurocImu(folder.path() / "written.csv", samples);
      require(sameSamples(datasets::readEurocImu(folder.path() / "written.csv"), samples));
      return;
    }
    case Choice::kStates: {
      std::vector<GroundTruthState> states;
      if (!parsedOrNamedError({name}, [&] { states = datasets::readGroundTruthStates(path); })) return;
      datasets::writeGroundTruthStates(folder.path() / "written.csv", states);
      const std::vector<GroundTruthState> reread = datasets::readGroundTruthStates(folder.path() / "written.csv");
      require(reread.size() == states.size());
      for (std::size_t i = 0; i < states.size(); ++i) {
        require(reread[i].t_ns == states[i].t_ns && reread[i].p_W_S == states[i].p_W_S &&
                reread[i].v_W_S == states[i].v_W_S && reread[i].b_g == states[i].b_g && reread[i].b_a == states[i].b_a);
      }
      return;
    }
    case Choice::kTrajectory:
      parsedOrNamedError({name}, [&] { eval::parseTum(asText(bytes), name); });
      return;
    case Choice::kEstimated:
      parsedOrNamedError({name}, [&] { eval::readEstimatedStates(path); });
      return;
    default:
      return;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const ScratchFolder folder;
  if (size == 0) return 0;
  const auto choice = static_cast<Choice>(data[0] % static_cast<std::uint8_t>(Choice::kCount));
  const Layout& layout = kLayouts[static_cast<std::size_t>(choice)];
  const std::span<const std::uint8_t> input(data + 1, size - 1);
  folder.clear();
  if (layout.source_prefix == nullptr) {
    readFile(folder, choice, input);
    return 0;
  }
  // Files the input does not reach are absent, as optional files of a layout may be.
  const auto parts = splitAtNul(input, layout.files.size());
  for (std::size_t i = 0; i < parts.size(); ++i) folder.write(layout.files[i], parts[i]);
  readFolder(folder, layout);
  return 0;
}
