#include "map_file_fixture.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "vifusion/core/little_endian.hpp"

namespace vifusion::mapfile::test {
namespace {

loop::FernOptions sampleFernOptions() {
  loop::FernOptions options;
  options.num_ferns = 60;
  options.downsample_factor = 8;
  options.capacity = 12;
  options.seed = 7;
  return options;
}
constexpr int kInputWidth = 64, kInputHeight = 48;  // 8×6 fern images

SE3d randomPose(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  const Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  return SE3d(q, Eigen::Vector3d(normal(rng), normal(rng), normal(rng)));
}

}  // namespace

SampleMap::SampleMap(std::uint64_t seed, std::uint32_t surfel_count)
    : keyframes(std::in_place, sampleFernOptions(), kInputWidth, kInputHeight) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  meta = {"rgbdi", 321, 1'000'000'000, 11'700'000'000};
  calibration.camera = PinholeCamera::create(320, 240, 262.5, -262.5, 159.5, 119.5);
  calibration.depth_camera =
      DepthCameraCalibration{PinholeCamera::create(480, 360, 300.0, 300.0, 240.0, 180.0), randomPose(rng)};
  calibration.depth_scale_m = 1e-3;
  calibration.inverse_depth_bias_per_m = 1.4e-3;
  calibration.T_S_C = randomPose(rng);
  calibration.time_shift_cam_imu_ns = -2'500'000;
  calibration.imu = ImuNoiseParams::zr300();
  NavState x;
  x.r_W_C = Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  x.q_W_C = randomPose(rng).quaternion();
  x.v_I_S = Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  x.b_g = 1e-3 * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  x.b_a = 1e-2 * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  x.q_I_W = randomPose(rng).quaternion();
  state = x;
  for (int k = 0; k < 321; ++k) trajectory.push_back({1'000'000'000 + k * 33'333'333LL, randomPose(rng)});

  loop::FernFrame frame = keyframes->makeFrame();
  std::uniform_int_distribution<int> byte(0, 255), code(0, loop::kFernCodeCount);
  for (int k = 0; k < 5; ++k) {
    for (int fern = 0; fern < frame.codes.size(); ++fern) {
      const int c = code(rng);
      frame.codes.set(fern, c == loop::kFernCodeCount ? loop::kInvalidFernCode : static_cast<std::uint8_t>(c));
    }
    for (int y = 0; y < frame.image.height(); ++y)
      for (int x = 0; x < frame.image.width(); ++x) {
        frame.image.rgb.view().row(y)[x] =
            Rgb8{static_cast<std::uint8_t>(byte(rng)), static_cast<std::uint8_t>(byte(rng)),
                 static_cast<std::uint8_t>(byte(rng))};
        frame.image.depth_m.view().row(y)[x] = static_cast<float>(std::abs(normal(rng)) * 2.0);
      }
    keyframes->restore(frame, randomPose(rng), 1'000'000'000 + 60 * k * 33'333'333LL,
                       static_cast<std::uint32_t>(60 * k));
  }

  surfels_header = {surfel_count, surfel_count / 3, 320};
  surfels.resize(std::size_t{surfel_count} * kSurfelFloats);
  for (std::size_t i = 0; i < surfels.size(); ++i) surfels[i] = static_cast<float>(normal(rng));
  // Colour words hold RGB8 bits, not numbers: keep a few patterns that arithmetic would not preserve.
  std::uniform_int_distribution<std::uint32_t> rgb(0, 0xFFFFFF);
  for (std::size_t s = 0; s < surfel_count; ++s) surfels[s * kSurfelFloats + 8] = std::bit_cast<float>(rgb(rng));
}

void writeSampleMap(const SampleMap& map, const std::string& path, std::size_t buffer_bytes,
                    std::size_t chunk_surfels) {
  MapFileWriter writer(path, buffer_bytes);
  writeMeta(writer, map.meta);
  writeCalibration(writer, map.calibration);
  writeState(writer, map.state);
  writeTrajectory(writer, map.trajectory);
  writeKeyframes(writer, map.keyframes ? &*map.keyframes : nullptr);
  beginSurfels(writer, map.surfels_header);
  for (std::size_t first = 0; first < map.surfels_header.surfel_count; first += chunk_surfels) {
    const std::size_t n = std::min<std::size_t>(chunk_surfels, map.surfels_header.surfel_count - first);
    writer.putF32s(std::span<const float>(map.surfels).subspan(first * kSurfelFloats, n * kSurfelFloats));
  }
  writer.endSection();
  writer.commit();
}

void copyMapFile(const std::string& path_in, const std::string& path_out, std::size_t buffer_bytes) {
  MapFileReader reader(path_in, buffer_bytes);
  MapFileWriter writer(path_out, buffer_bytes);
  writeMeta(writer, readMeta(reader));
  writeCalibration(writer, readCalibration(reader));
  writeState(writer, readState(reader));
  writeTrajectory(writer, readTrajectory(reader));
  const std::optional<loop::FernDatabase> keyframes = readKeyframes(reader);
  writeKeyframes(writer, keyframes ? &*keyframes : nullptr);
  const SurfelsHeader header = beginSurfels(reader);
  beginSurfels(writer, header);
  std::vector<float> surfel(kSurfelFloats);
  for (std::uint32_t s = 0; s < header.surfel_count; ++s) {
    reader.getF32s(surfel);
    writer.putF32s(surfel);
  }
  reader.endSection();
  writer.endSection();
  reader.finish();
  writer.commit();
}

std::vector<SectionPlace> sectionPlaces(const std::vector<std::uint8_t>& file) {
  std::vector<SectionPlace> places;
  std::uint64_t offset = kFileHeaderBytes;
  for (int s = 0; s < kSectionCount; ++s) {
    SectionPlace place{static_cast<MapSection>(s), offset, offset + kSectionHeaderBytes,
                       loadU64(file.data() + offset + kSectionTagBytes)};
    places.push_back(place);
    offset = place.payload_offset + place.payload_bytes;
  }
  EXPECT_EQ(offset, file.size());
  return places;
}

std::vector<std::uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

std::string temporaryPath(const std::string& name) {
  const std::filesystem::path directory = std::filesystem::path(::testing::TempDir()) / "vifusion_mapfile";
  std::filesystem::create_directories(directory);
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return (directory / (std::string(info->name()) + "_" + name)).string();
}

}  // namespace vifusion::mapfile::test
