#include <gtest/gtest.h>

#include <filesystem>

#include "map_file_fixture.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/mapfile/map_file_check.hpp"

namespace vifusion::mapfile::test {
namespace {

void expectSamePose(const SE3d& a, const SE3d& b) {
  EXPECT_EQ(a.quaternion().coeffs(), b.quaternion().coeffs());
  EXPECT_EQ(a.translation(), b.translation());
}

TEST(MapFile, EverySectionReadsBackAsWritten) {
  const SampleMap map(1);
  const std::string path = temporaryPath("map.vifmap");
  writeSampleMap(map, path);

  MapFileReader reader(path);
  EXPECT_EQ(reader.formatVersion(), kFormatVersion);
  EXPECT_EQ(readMeta(reader), map.meta);
  const RigCalibration calibration = readCalibration(reader);
  EXPECT_EQ(calibration.camera.width, 320);
  EXPECT_EQ(calibration.camera.fy, -262.5);
  ASSERT_TRUE(calibration.depth_camera.has_value());
  EXPECT_EQ(calibration.depth_camera->camera.width, 480);
  expectSamePose(calibration.depth_camera->T_C_D, map.calibration.depth_camera->T_C_D);
  expectSamePose(calibration.T_S_C, map.calibration.T_S_C);
  EXPECT_EQ(calibration.time_shift_cam_imu_ns, -2'500'000);
  EXPECT_EQ(calibration.imu.static_accel_bias_mps2, map.calibration.imu.static_accel_bias_mps2);
  EXPECT_EQ(calibration.imu.accel_noise_density, map.calibration.imu.accel_noise_density);
  EXPECT_EQ(calibration.g_W, map.calibration.g_W);
  const std::optional<NavState> state = readState(reader);
  ASSERT_TRUE(state.has_value());
  EXPECT_EQ(state->q_I_W.coeffs(), map.state->q_I_W.coeffs());  // the gravity direction in W
  EXPECT_EQ(state->b_a, map.state->b_a);
  EXPECT_EQ(state->b_g, map.state->b_g);
  EXPECT_EQ(state->v_I_S, map.state->v_I_S);
  const std::vector<StampedPose> trajectory = readTrajectory(reader);
  ASSERT_EQ(trajectory.size(), map.trajectory.size());
  for (std::size_t k = 0; k < trajectory.size(); ++k) {
    EXPECT_EQ(trajectory[k].t_ns, map.trajectory[k].t_ns);
    expectSamePose(trajectory[k].T_W_C, map.trajectory[k].T_W_C);
  }
  const std::optional<loop::FernDatabase> saved = readKeyframes(reader);
  ASSERT_TRUE(saved.has_value());
  const loop::FernDatabase& keyframes = *saved;
  EXPECT_EQ(keyframes.options().seed, 7u);
  EXPECT_EQ(keyframes.encoder().ferns(), map.keyframes->encoder().ferns());  // the seed draws the same ferns
  ASSERT_EQ(keyframes.size(), map.keyframes->size());
  for (std::int32_t id = 0; id < keyframes.size(); ++id) {
    const loop::FernKeyframe a = keyframes.keyframe(id), b = map.keyframes->keyframe(id);
    expectSamePose(a.T_W_C, b.T_W_C);
    EXPECT_EQ(a.frame_index, b.frame_index);
    EXPECT_TRUE(std::equal(a.codes.begin(), a.codes.end(), b.codes.begin(), b.codes.end()));
    EXPECT_EQ(a.valid_count, b.valid_count);
    for (int y = 0; y < a.rgb.height; ++y)
      for (int x = 0; x < a.rgb.width; ++x) {
        EXPECT_EQ(a.rgb.row(y)[x], b.rgb.row(y)[x]);
        EXPECT_EQ(a.depth_m.row(y)[x], b.depth_m.row(y)[x]);
      }
    // The restored database answers queries as the original does.
    loop::FernCodes codes(keyframes.options().num_ferns);
    for (int f = 0; f < codes.size(); ++f) codes.set(f, a.codes[static_cast<std::size_t>(f)]);
    loop::FernDatabase original = *map.keyframes;
    loop::FernDatabase restored = keyframes;
    EXPECT_EQ(restored.nearest(codes).keyframe, original.nearest(codes).keyframe);
  }
  EXPECT_EQ(beginSurfels(reader), map.surfels_header);
  std::vector<float> surfels(map.surfels.size());
  reader.getF32s(surfels);
  reader.endSection();
  reader.finish();
  EXPECT_EQ(0, std::memcmp(surfels.data(), map.surfels.data(), surfels.size() * sizeof(float)));  // bit for bit
}

TEST(MapFile, SaveLoadSaveIsByteIdentical) {
  // The round trip the issue asks for, through buffers far smaller than the sections (every payload crosses
  // many buffer refills and the large ones are checked only at their end) and through the default ones.
  const SampleMap map(2, 3000);
  const std::string first = temporaryPath("first.vifmap");
  writeSampleMap(map, first);
  for (const std::size_t buffer_bytes : {std::size_t{64}, std::size_t{1000}, MapFileWriter::kDefaultBufferBytes}) {
    const std::string second = temporaryPath("second_" + std::to_string(buffer_bytes) + ".vifmap");
    copyMapFile(first, second, buffer_bytes);
    EXPECT_EQ(readBytes(second), readBytes(first)) << "buffers of " << buffer_bytes << " bytes";
  }
  // Written through small buffers and in other chunks, the same bytes too.
  const std::string small = temporaryPath("small.vifmap");
  writeSampleMap(map, small, 100, 7);
  EXPECT_EQ(readBytes(small), readBytes(first));
}

TEST(MapFile, CheckSummarisesASoundFile) {
  const SampleMap map(3, 500);
  const std::string path = temporaryPath("map.vifmap");
  writeSampleMap(map, path);
  const MapFileSummary summary = checkMapFile(path);
  EXPECT_EQ(summary.format_version, kFormatVersion);
  EXPECT_EQ(summary.file_bytes, std::filesystem::file_size(path));
  EXPECT_EQ(summary.meta, map.meta);
  EXPECT_TRUE(summary.has_state);
  EXPECT_EQ(summary.trajectory_poses, map.trajectory.size());
  EXPECT_EQ(summary.keyframes, 5);
  EXPECT_EQ(summary.surfels, map.surfels_header);
  EXPECT_EQ(summary.section_bytes[static_cast<std::size_t>(MapSection::kSurfels)], 12u + 500u * 48u);
  EXPECT_EQ(summary.section_bytes[static_cast<std::size_t>(MapSection::kTrajectory)], 8u + 321u * 64u);
  EXPECT_EQ(summary.section_bytes[static_cast<std::size_t>(MapSection::kEnd)], 0u);
  // The sizes the README's layout table gives.
  EXPECT_EQ(summary.section_bytes[static_cast<std::size_t>(MapSection::kMeta)], 24u + 5u);     // "rgbdi"
  EXPECT_EQ(summary.section_bytes[static_cast<std::size_t>(MapSection::kCalibration)], 345u);  // with a depth camera
  EXPECT_EQ(summary.section_bytes[static_cast<std::size_t>(MapSection::kState)], 161u);
  EXPECT_EQ(summary.section_bytes[static_cast<std::size_t>(MapSection::kKeyframes)],
            57u + 5u * (68u + 60u + 7u * 8u * 6u));  // 5 keyframes, 60 ferns, 8×6 fern images
}

TEST(MapFile, AnRgbdMapHasNoState) {
  SampleMap map(4, 0);
  map.state.reset();
  map.calibration.depth_camera.reset();
  map.keyframes.reset();
  const std::string path = temporaryPath("map.vifmap");
  writeSampleMap(map, path);
  const MapFileSummary summary = checkMapFile(path);
  EXPECT_FALSE(summary.has_state);
  EXPECT_FALSE(summary.calibration.depth_camera.has_value());
  EXPECT_EQ(summary.keyframes, 0);
  EXPECT_EQ(summary.section_bytes[static_cast<std::size_t>(MapSection::kKeyframes)], 1u);
  EXPECT_EQ(summary.section_bytes[static_cast<std::size_t>(MapSection::kCalibration)], 249u);
  EXPECT_EQ(summary.section_bytes[static_cast<std::size_t>(MapSection::kState)], 1u);
  EXPECT_EQ(summary.surfels.surfel_count, 0u);
}

TEST(MapFile, TheFileHeaderIsAsDocumented) {
  // map_file_format.hpp's layout, read here byte by byte: a reader in another language needs nothing else.
  const SampleMap map(5, 10);
  const std::string path = temporaryPath("map.vifmap");
  writeSampleMap(map, path);
  const std::vector<std::uint8_t> bytes = readBytes(path);
  ASSERT_GE(bytes.size(), kFileHeaderBytes + kSectionHeaderBytes);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 8), "VIFUSMAP");
  EXPECT_EQ(bytes[8], 1);  // version 1, little-endian
  EXPECT_EQ(bytes[9] | bytes[10] | bytes[11], 0);
  EXPECT_EQ(std::string(bytes.begin() + 16, bytes.begin() + 20), "meta");
  EXPECT_EQ(bytes[20], 0);  // NUL-padded tag
  const std::vector<SectionPlace> places = sectionPlaces(bytes);
  ASSERT_EQ(places.size(), static_cast<std::size_t>(kSectionCount));
  EXPECT_EQ(places.back().payload_bytes, 0u);
  EXPECT_EQ(std::string(bytes.begin() + static_cast<std::ptrdiff_t>(places.back().header_offset),
                        bytes.begin() + static_cast<std::ptrdiff_t>(places.back().header_offset) + 3),
            "end");
  // meta's payload: str "rgbdi" then u32 frames.
  const std::size_t meta = places.front().payload_offset;
  EXPECT_EQ(bytes[meta], 5);
  EXPECT_EQ(std::string(bytes.begin() + static_cast<std::ptrdiff_t>(meta) + 4,
                        bytes.begin() + static_cast<std::ptrdiff_t>(meta) + 9),
            "rgbdi");
  EXPECT_EQ(bytes[meta + 9] | bytes[meta + 10] << 8, 321);
}

TEST(MapFileWriter, AFileAppearsOnlyWhenCommitted) {
  const std::string path = temporaryPath("map.vifmap");
  const SampleMap old_map(6, 10);
  writeSampleMap(old_map, path);
  const std::vector<std::uint8_t> before = readBytes(path);
  const auto directoryEntries = [&] {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(path).parent_path())) {
      names.push_back(entry.path().filename().string());
    }
    return names;
  };
  const std::vector<std::string> entries = directoryEntries();
  {
    MapFileWriter writer(path);
    writeMeta(writer, SampleMap(7, 10).meta);
    // Nothing of the new file is visible while it is written: a SIGKILL here leaves no partial file.
    EXPECT_EQ(directoryEntries(), entries);
    // abandoned (an exception, a full disk, a stop) before commit()
  }
  EXPECT_EQ(directoryEntries(), entries);
  EXPECT_EQ(readBytes(path), before);
}

TEST(MapFileWriter, RefusesSectionsOutOfOrderAndAnUnwritablePath) {
  const std::string path = temporaryPath("map.vifmap");
  MapFileWriter writer(path);
  EXPECT_THROW(writeCalibration(writer, RigCalibration{}), Error);  // meta comes first
  EXPECT_THROW(writer.commit(), Error);
  try {
    MapFileWriter nowhere("/nonexistent-directory/map.vifmap");
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent-directory/map.vifmap"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace vifusion::mapfile::test
