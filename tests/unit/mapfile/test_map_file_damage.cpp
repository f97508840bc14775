// A damaged map file is refused with the section named: every section cut short, one byte flipped in every
// section's payload and header, the file cut at every section boundary, a newer format version, a value that
// passes the checksum but cannot be right.
#include <gtest/gtest.h>

#include <filesystem>
#include <iterator>

#include "map_file_fixture.hpp"
#include "vifusion/core/crc32.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/little_endian.hpp"
#include "vifusion/mapfile/map_file_check.hpp"

namespace vifusion::mapfile::test {
namespace {

/// checkMapFile's error for the file, or "" when it was accepted. Small buffers too: a large section is
/// then checked only at its end, and the message must still name it.
std::string refusal(const std::vector<std::uint8_t>& bytes, const std::string& name) {
  const std::string path = temporaryPath(name);
  writeBytes(path, bytes);
  try {
    checkMapFile(path);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string quoted(MapSection section) {  // appended: GCC 12's -Wrestrict misfires on "'" + std::string(…)
  std::string text(1, '\'');
  text += sectionName(section);
  text += '\'';
  return text;
}

class DamagedMapFile : public ::testing::Test {
 protected:
  void SetUp() override {
    const SampleMap map(11, 40'000);  // surfels: 1.9 MB, larger than the reader's buffer
    path_ = temporaryPath("sound.vifmap");
    writeSampleMap(map, path_);
    sound_ = readBytes(path_);
    places_ = sectionPlaces(sound_);
  }
  std::string path_;
  std::vector<std::uint8_t> sound_;
  std::vector<SectionPlace> places_;
};

TEST_F(DamagedMapFile, TheSoundFileIsAccepted) { EXPECT_EQ(refusal(sound_, "copy.vifmap"), ""); }

TEST_F(DamagedMapFile, AByteFlippedInAnyPayloadNamesItsSection) {
  for (const SectionPlace& place : places_) {
    if (place.payload_bytes == 0) continue;
    for (const std::uint64_t at : {place.payload_offset, place.payload_offset + place.payload_bytes / 2,
                                   place.payload_offset + place.payload_bytes - 1}) {
      std::vector<std::uint8_t> bytes = sound_;
      bytes[at] ^= 0x10;
      const std::string error = refusal(bytes, "flipped.vifmap");
      // A section larger than the reader's buffer is decoded before its checksum is known: a flipped count
      // is then found by the sizes that disagree, the rest by the checksum at its end.
      const bool checked_whole = place.payload_bytes <= MapFileReader::kDefaultBufferBytes;
      EXPECT_TRUE(contains(error, "section " + quoted(place.section) + ": ") &&
                  (contains(error, "corrupt") || (!checked_whole && at == place.payload_offset)))
          << "byte " << at << " of section " << quoted(place.section) << ": " << error;
    }
  }
}

TEST_F(DamagedMapFile, AByteFlippedInASectionHeaderIsFound) {
  for (const SectionPlace& place : places_) {
    for (std::uint64_t at = place.header_offset; at < place.payload_offset; at += 5) {
      std::vector<std::uint8_t> bytes = sound_;
      bytes[at] ^= 0x01;
      const std::string error = refusal(bytes, "header.vifmap");
      const std::string after = place.section == MapSection::kMeta
                                    ? "the file header"
                                    : "section " + quoted(static_cast<MapSection>(static_cast<int>(place.section) - 1));
      EXPECT_TRUE(contains(error, "header of the section after " + after) && contains(error, "corrupt"))
          << "byte " << at - place.header_offset << " of the header of " << quoted(place.section) << ": " << error;
    }
  }
}

TEST_F(DamagedMapFile, EverySectionCutShortIsNamed) {
  for (const SectionPlace& place : places_) {
    if (place.payload_bytes == 0) continue;
    for (const std::uint64_t keep : {std::uint64_t{0}, place.payload_bytes / 2, place.payload_bytes - 1}) {
      const std::vector<std::uint8_t> bytes(sound_.begin(),
                                            sound_.begin() + static_cast<std::ptrdiff_t>(place.payload_offset + keep));
      const std::string error = refusal(bytes, "cut.vifmap");
      EXPECT_TRUE(contains(error, "section " + quoted(place.section) + ": cut: " + std::to_string(keep) + " of its " +
                                      std::to_string(place.payload_bytes) + " bytes"))
          << error;
    }
  }
}

TEST_F(DamagedMapFile, AFileCutBetweenSectionsSaysWhatIsMissing) {
  for (std::size_t s = 0; s < places_.size(); ++s) {
    const std::vector<std::uint8_t> bytes(sound_.begin(),
                                          sound_.begin() + static_cast<std::ptrdiff_t>(places_[s].header_offset));
    const std::string after = s == 0 ? "the file header" : "section " + quoted(places_[s - 1].section);
    const std::string error = refusal(bytes, "boundary.vifmap");
    EXPECT_TRUE(contains(error, "ends after " + after + ": section " + quoted(places_[s].section) + " and the rest"))
        << error;
  }
  // Inside a section header.
  const std::vector<std::uint8_t> bytes(sound_.begin(),
                                        sound_.begin() + static_cast<std::ptrdiff_t>(places_[2].header_offset + 10));
  EXPECT_TRUE(contains(refusal(bytes, "in_header.vifmap"), "ends after section 'calib'"));
}

TEST_F(DamagedMapFile, BytesAfterTheEndAreRefused) {
  std::vector<std::uint8_t> bytes = sound_;
  bytes.push_back(0);
  EXPECT_TRUE(contains(refusal(bytes, "trailing.vifmap"), "1 bytes follow its end section"));
}

TEST_F(DamagedMapFile, ANewerVersionIsRefusedWithWhatToDo) {
  std::vector<std::uint8_t> bytes = sound_;
  storeU32(bytes.data() + 8, kFormatVersion + 1);
  storeU32(bytes.data() + 12, crc32(std::span<const std::uint8_t>(bytes.data(), 12)));
  const std::string error = refusal(bytes, "newer.vifmap");
  EXPECT_TRUE(contains(error, "map format version 2, newer than this vifusion reads (1)")) << error;
}

TEST_F(DamagedMapFile, NotAMapFile) {
  EXPECT_TRUE(contains(refusal({}, "empty.vifmap"), "is not a vifusion map file (0 bytes)"));
  const std::vector<std::uint8_t> ply = {'p', 'l', 'y', '\n', 'f', 'o', 'r', 'm', 'a', 't', ' ',
                                         'a', 's', 'c', 'i',  'i', ' ', '1', '.', '0', '\n'};
  EXPECT_TRUE(contains(refusal(ply, "map.ply"), "is not a vifusion map file"));
  std::vector<std::uint8_t> bytes = sound_;
  bytes[12] ^= 1;
  EXPECT_TRUE(contains(refusal(bytes, "header.vifmap"), "its file header is corrupt"));
}

std::size_t openDescriptors() {
  return static_cast<std::size_t>(
      std::distance(std::filesystem::directory_iterator("/proc/self/fd"), std::filesystem::directory_iterator()));
}

// Found by fuzz_map_file: a file refused by its header kept its descriptor (the constructor threw, so no
// destructor closed it), and a service retrying a damaged map would run out of them.
TEST_F(DamagedMapFile, ARefusedFileKeepsNoDescriptorOpen) {
  std::vector<std::uint8_t> bytes = sound_;
  bytes[12] ^= 1;
  const std::size_t before = openDescriptors();
  for (int attempt = 0; attempt < 50; ++attempt) {
    EXPECT_TRUE(contains(refusal(bytes, "header.vifmap"), "its file header is corrupt"));
    EXPECT_TRUE(contains(refusal({}, "empty.vifmap"), "is not a vifusion map file"));
  }
  EXPECT_EQ(openDescriptors(), before);
}

TEST_F(DamagedMapFile, AValueThatCannotBeRightIsNamedEvenWithAValidChecksum) {
  // Damage that a checksum cannot see (the writer's own bug, or a file made by another tool): a NaN in a
  // trajectory pose, with the section's CRC recomputed.
  const SectionPlace& traj = places_[static_cast<std::size_t>(MapSection::kTrajectory)];
  std::vector<std::uint8_t> bytes = sound_;
  const std::uint64_t first_pose_tx = traj.payload_offset + 8 + 8 + 4 * 8;  // count, t_ns, quaternion
  storeU64(bytes.data() + first_pose_tx, std::bit_cast<std::uint64_t>(std::numeric_limits<double>::quiet_NaN()));
  std::uint8_t* header = bytes.data() + traj.header_offset;
  storeU32(header + 16, crc32(std::span<const std::uint8_t>(bytes.data() + traj.payload_offset, traj.payload_bytes)));
  storeU32(header + 20, crc32(std::span<const std::uint8_t>(header, 20)));
  const std::string error = refusal(bytes, "nan.vifmap");
  EXPECT_TRUE(contains(error, "section 'traj': a trajectory pose is not finite")) << error;
}

}  // namespace
}  // namespace vifusion::mapfile::test
