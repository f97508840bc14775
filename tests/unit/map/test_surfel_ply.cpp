// The surfel map's PLY file: the header text exactly, every property of every vertex byte for byte
// (a parser here, independent of the writer), positions through eval::readPlyPositions, the
// min_confidence filter, and the atomic replacement (a failed write leaves the previous file and
// no temporary file).

#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "vifusion/eval/ply_points.hpp"
#include "vifusion/map/surfel_ply.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion {
namespace {

namespace fs = std::filesystem;
using map::Surfel;
using test::expectError;

static_assert(std::endian::native == std::endian::little, "the byte checks below read host floats as PLY bytes");

/// A fresh directory under the system temp directory, removed with everything in it.
class TempDirectory {
 public:
  TempDirectory() {
    std::string pattern = (fs::temp_directory_path() / "vifusion_surfel_ply_XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed for " + pattern);
    path_ = pattern;
  }
  ~TempDirectory() {
    std::error_code ignored;
    fs::permissions(path_, fs::perms::owner_all, fs::perm_options::add, ignored);
    fs::remove_all(path_, ignored);
  }
  TempDirectory(const TempDirectory&) = delete;
  TempDirectory& operator=(const TempDirectory&) = delete;
  const fs::path& path() const { return path_; }
  /// Names of the entries, sorted.
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const fs::directory_entry& entry : fs::directory_iterator(path_)) names.push_back(entry.path().filename());
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  fs::path path_;
};

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeFile(const fs::path& path, const std::string& contents) { std::ofstream(path, std::ios::binary) << contents; }

Surfel makeSurfel(Eigen::Vector3f p_W, Eigen::Vector3f n_W, Eigen::Vector3f rgb, float radius_m, float confidence) {
  Surfel s;
  s.position_confidence << p_W, confidence;
  s.normal_radius << n_W, radius_m;
  s.setPackedColour(map::packRgb8(rgb));
  s.colour_times.y() = 3.0f;
  s.colour_times.z() = 7.0f;
  return s;
}

/// `count` surfels with random finite values, colours and confidences in [0, 20).
std::vector<Surfel> randomSurfels(std::size_t count, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> coordinate(-5.0f, 5.0f), confidence(0.0f, 20.0f), radius(0.001f, 0.05f);
  std::uniform_int_distribution<int> channel(0, 255);
  std::vector<Surfel> surfels;
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3f p(coordinate(random), coordinate(random), coordinate(random));
    const Eigen::Vector3f n = Eigen::Vector3f(coordinate(random), coordinate(random), 1.0f).normalized();
    const Eigen::Vector3f rgb(channel(random), channel(random), channel(random));
    surfels.push_back(makeSurfel(p, n, rgb, radius(random), confidence(random)));
  }
  return surfels;
}

std::string expectedHeader(std::size_t vertices, const std::string& min_confidence) {
  std::string text =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "comment vifusion surfel map: x y z [m], nx ny nz in the map world frame W, radius [m]\n";
  text += "comment min_confidence " + min_confidence + "\n";
  text += "element vertex " + std::to_string(vertices) + "\n";
  return text +
         "property float x\n"
         "property float y\n"
         "property float z\n"
         "property float nx\n"
         "property float ny\n"
         "property float nz\n"
         "property uchar red\n"
         "property uchar green\n"
         "property uchar blue\n"
         "property float radius\n"
         "property float confidence\n"
         "end_header\n";
}

/// The 35 bytes a surfel's vertex must have: float x y z nx ny nz, uchar red green blue, float
/// radius confidence, little-endian.
std::string vertexBytes(const Surfel& s) {
  std::string bytes;
  const auto put = [&](float value) { bytes.append(reinterpret_cast<const char*>(&value), sizeof(value)); };
  for (int i = 0; i < 3; ++i) put(s.position_confidence[i]);
  for (int i = 0; i < 3; ++i) put(s.normal_radius[i]);
  const Eigen::Vector3f rgb = map::unpackRgb8(s.packedColour());
  for (int i = 0; i < 3; ++i) bytes.push_back(static_cast<char>(static_cast<unsigned char>(rgb[i])));
  put(s.normal_radius.w());
  put(s.position_confidence.w());
  return bytes;
}

/// Splits `path` into its header (through "end_header\n") and body, and checks both: the header
/// exactly, then the body vertex by vertex against `expected`.
void expectPly(const fs::path& path, const std::vector<Surfel>& expected, const std::string& min_confidence) {
  const std::string file = readFile(path);
  const std::string end = "end_header\n";
  const std::size_t body_start = file.find(end);
  ASSERT_NE(body_start, std::string::npos) << "no end_header";
  EXPECT_EQ(file.substr(0, body_start + end.size()), expectedHeader(expected.size(), min_confidence));
  const std::string body = file.substr(body_start + end.size());
  ASSERT_EQ(body.size(), expected.size() * 35);
  std::size_t mismatches = 0;
  for (std::size_t v = 0; v < expected.size(); ++v)
    mismatches += body.compare(v * 35, 35, vertexBytes(expected[v])) != 0;
  EXPECT_EQ(mismatches, 0u);
}

std::vector<Eigen::Vector3d> positions(const std::vector<Surfel>& surfels) {
  std::vector<Eigen::Vector3d> points;
  for (const Surfel& s : surfels) points.push_back(s.position_confidence.head<3>().cast<double>());
  return points;
}

TEST(SurfelPly, WritesTheDocumentedHeaderAndEveryPropertyByteForByte) {
  TempDirectory dir;
  const std::vector<Surfel> surfels = {
      makeSurfel({1.5f, -2.25f, 3.0f}, {0.0f, 0.0f, 1.0f}, {255, 0, 128}, 0.004f, 12.5f),
      makeSurfel({-0.1f, 0.2f, -0.3f}, {0.6f, -0.8f, 0.0f}, {1, 2, 3}, 0.0125f, 0.75f),
      makeSurfel({1e-7f, 1e7f, 0.0f}, {-1.0f, 0.0f, 0.0f}, {0, 255, 0}, 0.1f, 100.0f)};
  const fs::path path = dir.path() / "map.ply";
  EXPECT_EQ(map::writeSurfelPly(path, surfels), surfels.size());
  expectPly(path, surfels, "0");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"map.ply"});
}

TEST(SurfelPly, PositionsRoundTripThroughTheEvaluationReader) {
  TempDirectory dir;
  // More vertices than one write() block of the writer.
  const std::vector<Surfel> surfels = randomSurfels(10'001, 1);
  const fs::path path = dir.path() / "map.ply";
  map::writeSurfelPly(path, surfels);
  EXPECT_EQ(eval::readPlyPositions(path), positions(surfels));
  expectPly(path, surfels, "0");
}

TEST(SurfelPly, AnEmptyMapIsAHeaderWithNoVertices) {
  TempDirectory dir;
  const fs::path path = dir.path() / "map.ply";
  EXPECT_EQ(map::writeSurfelPly(path, {}), 0u);
  EXPECT_EQ(readFile(path), expectedHeader(0, "0"));
  EXPECT_TRUE(eval::readPlyPositions(path).empty());
}

TEST(SurfelPly, MinConfidenceKeepsTheSurfelsAtOrAboveItInMapOrder) {
  TempDirectory dir;
  const std::vector<Surfel> surfels = randomSurfels(2000, 2);
  map::MapOptions map_options;
  map_options.confidence_threshold = 10.0f;
  const map::SurfelPlyOptions stable = map::SurfelPlyOptions::stableOnly(map_options);
  EXPECT_EQ(stable.min_confidence, 10.0f);

  std::vector<Surfel> kept;
  for (const Surfel& s : surfels) {
    if (s.position_confidence.w() >= 10.0f) kept.push_back(s);
  }
  ASSERT_GT(kept.size(), 500u);
  ASSERT_LT(kept.size(), 1500u);
  const fs::path path = dir.path() / "map.ply";
  EXPECT_EQ(map::writeSurfelPly(path, surfels, stable), kept.size());
  expectPly(path, kept, "10");
  EXPECT_EQ(eval::readPlyPositions(path), positions(kept));

  // Exactly at the threshold counts as stable, like the map's own rule.
  std::vector<Surfel> edge = {surfels[0], surfels[1]};
  edge[0].position_confidence.w() = 10.0f;
  edge[1].position_confidence.w() = std::nextafter(10.0f, 0.0f);
  EXPECT_EQ(map::writeSurfelPly(path, edge, stable), 1u);
  expectPly(path, {edge[0]}, "10");

  map::SurfelPlyOptions fractional;
  fractional.min_confidence = 2.5f;
  map::writeSurfelPly(path, surfels, fractional);
  EXPECT_NE(readFile(path).find("comment min_confidence 2.5\n"), std::string::npos);
}

TEST(SurfelPly, InvalidOptionsNameTheFieldAndWriteNothing) {
  TempDirectory dir;
  for (const float bad : {-1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    SCOPED_TRACE(bad);
    map::SurfelPlyOptions options;
    options.min_confidence = bad;
    expectError([&] { map::writeSurfelPly(dir.path() / "map.ply", randomSurfels(3, 3), options); },
                "surfel PLY option 'min_confidence' must be finite and ≥ 0");
  }
  EXPECT_TRUE(dir.entries().empty());
}

TEST(SurfelPly, ReplacesAnExistingFileAndAStaleTemporaryFile) {
  TempDirectory dir;
  const fs::path path = dir.path() / "map.ply";
  map::writeSurfelPly(path, randomSurfels(100, 4));
  writeFile(dir.path() / "map.ply.tmp", "left behind by a crash");
  const std::vector<Surfel> surfels = randomSurfels(50, 5);
  map::writeSurfelPly(path, surfels);
  expectPly(path, surfels, "0");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"map.ply"});
}

/// Limits the size of files this process writes (RLIMIT_FSIZE, enforced for root too), with
/// SIGXFSZ ignored so a write past the limit fails with EFBIG: a disk filling up mid-write.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    EXPECT_EQ(::getrlimit(RLIMIT_FSIZE, &saved_), 0);
    previous_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    EXPECT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, previous_handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit saved_{};
  void (*previous_handler_)(int) = nullptr;
};

TEST(SurfelPly, AWriteThatFailsMidwayLeavesThePreviousFileAndNoTemporaryFile) {
  TempDirectory dir;
  const fs::path path = dir.path() / "map.ply";
  map::writeSurfelPly(path, randomSurfels(100, 6));
  const std::string previous = readFile(path);
  {
    const FileSizeLimit limit(16 * 1024);  // the new file needs 350 kB
    expectError([&] { map::writeSurfelPly(path, randomSurfels(10'000, 7)); },
                path.string() + ": writing failed: File too large (the previous file is unchanged)");
  }
  EXPECT_EQ(readFile(path), previous);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"map.ply"});
}

TEST(SurfelPly, AFailedRenameLeavesTheTargetAndNoTemporaryFile) {
  TempDirectory dir;
  const fs::path path = dir.path() / "map.ply";
  fs::create_directory(path);  // rename() cannot replace a non-empty directory
  writeFile(path / "keep", "x");
  expectError([&] { map::writeSurfelPly(path, randomSurfels(10, 8)); },
              path.string() + ": renaming '" + path.string() + ".tmp' over it failed: ");
  EXPECT_EQ(readFile(path / "keep"), "x");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"map.ply"});
}

TEST(SurfelPly, AMissingDirectoryIsNamedInTheError) {
  TempDirectory dir;
  const fs::path path = dir.path() / "missing" / "map.ply";
  expectError(
      [&] { map::writeSurfelPly(path, randomSurfels(10, 9)); },
      path.string() + ": cannot create a file in '" + path.parent_path().string() + "': No such file or directory");
}

TEST(SurfelPly, AReadOnlyDirectoryKeepsThePreviousFile) {
  TempDirectory dir;
  const fs::path path = dir.path() / "map.ply";
  map::writeSurfelPly(path, randomSurfels(10, 10));
  const std::string previous = readFile(path);
  fs::permissions(dir.path(), fs::perms::owner_write | fs::perms::group_write | fs::perms::others_write,
                  fs::perm_options::remove);
  // Root ignores directory permissions (and CI runs as root), so the write is attempted by a child
  // process that first drops to the unprivileged user `nobody` (65534).
  const std::string expected =
      path.string() + ": cannot create a file in '" + dir.path().string() + "': Permission denied";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) ::_exit(3);
    try {
      map::writeSurfelPly(path, randomSurfels(20, 11));
      ::_exit(1);  // the write should have failed
    } catch (const Error& error) {
      ::_exit(std::string(error.what()) == expected ? 0 : 2);
    }
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: the write succeeded, 2: another message than: " << expected;
  fs::permissions(dir.path(), fs::perms::owner_write, fs::perm_options::add);
  EXPECT_EQ(readFile(path), previous);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"map.ply"});
}

}  // namespace
}  // namespace vifusion
