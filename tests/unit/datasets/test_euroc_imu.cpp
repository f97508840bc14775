#include <gtest/gtest.h>

#include <vector>

#include "fixtures.hpp"
#include "vifusion/datasets/euroc_imu.hpp"
#include "vifusion/datasets/ground_truth_states.hpp"
#include "vifusion/test/data_paths.hpp"

namespace vifusion::datasets::test {
namespace {

constexpr const char* kHeader =
    "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],"
    "a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n";

TEST(EurocImu, ReadsRealEurocV101Exactly) {
  const std::vector<ImuSample> samples = readEurocImu(vifusion::test::dataDir() / "euroc-v1-01-imu" / "imu0.csv");
  ASSERT_EQ(samples.size(), 29085u);
  // First data line: 1403715273262142976,-0.0020943951023931952,0.017453292519943295,0.07749261878854824,
  //                  9.0874956666666655,0.13075533333333333,-3.6938381666666662
  EXPECT_EQ(samples[0].t_ns, 1403715273262142976);
  EXPECT_EQ(samples[0].gyro_rad_s.x(), -0.0020943951023931952);
  EXPECT_EQ(samples[0].gyro_rad_s.y(), 0.017453292519943295);
  EXPECT_EQ(samples[0].gyro_rad_s.z(), 0.07749261878854824);
  EXPECT_EQ(samples[0].accel_mps2.x(), 9.0874956666666655);
  EXPECT_EQ(samples[0].accel_mps2.y(), 0.13075533333333333);
  EXPECT_EQ(samples[0].accel_mps2.z(), -3.6938381666666662);
  EXPECT_EQ(samples[1].t_ns, 1403715273267142912);
  for (std::size_t k = 1; k < samples.size(); ++k) ASSERT_GT(samples[k].t_ns, samples[k - 1].t_ns);
}

TEST(EurocImu, FindsColumnsByNameWhateverTheOrder) {
  TempDir dir;
  writeText(dir / "imu.csv",
            "#timestamp [ns], a_RS_S_x, a_RS_S_y, a_RS_S_z, w_RS_S_x, w_RS_S_y, w_RS_S_z\r\n"
            "100,1.5,2.5,3.5,0.1,0.2,0.3\r\n");
  const std::vector<ImuSample> samples = readEurocImu(dir / "imu.csv");
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_EQ(samples[0].t_ns, 100);
  EXPECT_EQ(samples[0].accel_mps2, Eigen::Vector3d(1.5, 2.5, 3.5));
  EXPECT_EQ(samples[0].gyro_rad_s, Eigen::Vector3d(0.1, 0.2, 0.3));
}

TEST(EurocImu, WriterRoundTripsBitExact) {
  TempDir dir;
  std::vector<ImuSample> samples(3);
  for (int k = 0; k < 3; ++k) {
    samples[static_cast<std::size_t>(k)].t_ns = 1'000'000'000'000 + 5'000'000 * k;
    samples[static_cast<std::size_t>(k)].gyro_rad_s = Eigen::Vector3d(0.1 / 3.0, -1e-17, k * 3.14159265358979);
    samples[static_cast<std::size_t>(k)].accel_mps2 = Eigen::Vector3d(9.81 / 7.0, 1e300, -2.0 / 3.0);
  }
  writeEurocImu(dir / "imu.csv", samples);
  const std::vector<ImuSample> read = readEurocImu(dir / "imu.csv");
  ASSERT_EQ(read.size(), samples.size());
  for (std::size_t k = 0; k < samples.size(); ++k) {
    EXPECT_EQ(read[k].t_ns, samples[k].t_ns);
    EXPECT_EQ(read[k].gyro_rad_s, samples[k].gyro_rad_s);
    EXPECT_EQ(read[k].accel_mps2, samples[k].accel_mps2);
  }
}

TEST(EurocImu, RejectsMissingHeader) {
  TempDir dir;
  writeText(dir / "imu.csv", "100,0,0,0,0,0,9.81\n");
  expectError([&] { readEurocImu(dir / "imu.csv"); }, "imu.csv line 1: expected the header");
}

TEST(EurocImu, RejectsHeaderWithoutAColumn) {
  TempDir dir;
  writeText(dir / "imu.csv", "#timestamp [ns],w_RS_S_x,w_RS_S_y,w_RS_S_z,a_RS_S_x,a_RS_S_y\n");
  expectError([&] { readEurocImu(dir / "imu.csv"); }, "imu.csv line 1: header lacks column 'a_RS_S_z'");
}

TEST(EurocImu, RejectsRowWithMissingColumn) {
  TempDir dir;
  writeText(dir / "imu.csv", std::string(kHeader) + "100,0,0,0,0,0,9.81\n200,0,0,0,0,0\n");
  expectError([&] { readEurocImu(dir / "imu.csv"); }, "imu.csv line 3: column 'a_RS_S_z' is missing (6 of 7 columns)");
}

TEST(EurocImu, RejectsNaN) {
  TempDir dir;
  writeText(dir / "imu.csv", std::string(kHeader) + "100,0,0,0,0,0,9.81\n200,0,0,0,0,0,9.81\n300,0,nan,0,0,0,9.81\n");
  expectError([&] { readEurocImu(dir / "imu.csv"); }, "imu.csv line 4: column 'w_RS_S_y' is not a number: 'nan'");
}

TEST(EurocImu, RejectsInfinityAndGarbage) {
  TempDir dir;
  writeText(dir / "a.csv", std::string(kHeader) + "100,0,0,0,inf,0,9.81\n");
  expectError([&] { readEurocImu(dir / "a.csv"); }, "a.csv line 2: column 'a_RS_S_x' is not finite: 'inf'");
  writeText(dir / "b.csv", std::string(kHeader) + "1e5,0,0,0,0,0,9.81\n");
  expectError([&] { readEurocImu(dir / "b.csv"); }, "b.csv line 2: column 'timestamp' is not an integer: '1e5'");
}

// Issue 22: a dataset reader leaves a bad row out and says why, and keeps the rows around it; the header must
// still be sound.
TEST(EurocImu, WithSkippedRowsABadRowIsLeftOutAndNamed) {
  TempDir dir;
  writeText(dir / "imu.csv", std::string(kHeader) +
                                 "10000000,0,0,0,0,0,9.81\n"
                                 "15000000,0,nan,0,0,0,9.81\n"
                                 "20000000,0,0,0,0,0,9.81\n"
                                 "12000000,0,0,0,0,0,9.81\n"
                                 "25000000,0,0,0,0,0\n"
                                 "30000000,0.5,0,0,0,0,9.81\n");
  std::vector<std::string> skipped;
  const std::vector<ImuSample> samples = readEurocImu(dir / "imu.csv", &skipped);
  ASSERT_EQ(samples.size(), 3u);
  EXPECT_EQ(samples[1].t_ns, 20'000'000);
  EXPECT_EQ(samples[2].t_ns, 30'000'000);
  EXPECT_EQ(samples[2].gyro_rad_s.x(), 0.5);
  EXPECT_EQ(skipped, (std::vector<std::string>{"imu.csv line 3: column 'w_RS_S_y' is not a number: 'nan'",
                                               "imu.csv line 5: timestamp goes backwards by 8 ms",
                                               "imu.csv line 6: column 'a_RS_S_z' is missing (6 of 7 columns)"}));
  writeText(dir / "no_header.csv", "10000000,0,0,0,0,0,9.81\n");
  expectError([&] { readEurocImu(dir / "no_header.csv", &skipped); }, "no_header.csv line 1: expected the header");
}

TEST(EurocImu, RejectsTimeGoingBackwardsOrRepeating) {
  TempDir dir;
  writeText(dir / "imu.csv", std::string(kHeader) + "10000000,0,0,0,0,0,9.81\n5000000,0,0,0,0,0,9.81\n");
  expectError([&] { readEurocImu(dir / "imu.csv"); }, "imu.csv line 3: timestamp goes backwards by 5 ms");
  writeText(dir / "rep.csv", std::string(kHeader) + "10000000,0,0,0,0,0,9.81\n10000000,0,0,0,0,0,9.81\n");
  expectError([&] { readEurocImu(dir / "rep.csv"); }, "rep.csv line 3: timestamp repeats the previous one");
}

TEST(EurocImu, RejectsStampsOutsideTheFileRange) {
  TempDir dir;
  writeText(dir / "neg.csv", std::string(kHeader) + "-5,0,0,0,0,0,9.81\n");
  expectError([&] { readEurocImu(dir / "neg.csv"); },
              "neg.csv line 2: column 'timestamp' is not a timestamp in nanoseconds between 0 and 4000000000000000000: "
              "'-5'");
  // A stamp near 2^63 ns followed by a small one: the step between them would overflow int64_t.
  writeText(dir / "big.csv", std::string(kHeader) + "9223372036854775000,0,0,0,0,0,9.81\n");
  expectError([&] { readEurocImu(dir / "big.csv"); }, "big.csv line 2: column 'timestamp' is not a timestamp");
}

TEST(EurocImu, RejectsMissingFile) {
  TempDir dir;
  expectError([&] { readEurocImu(dir / "imu.csv"); }, "imu.csv: cannot open file");
}

TEST(GroundTruthStates, WriterRoundTrips) {
  TempDir dir;
  std::vector<GroundTruthState> states(2);
  states[0].t_ns = 5;
  states[0].p_W_S = Eigen::Vector3d(1.0 / 3.0, -2.0, 1e-9);
  states[0].q_W_S = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  states[0].v_W_S = Eigen::Vector3d(0.5, 0.25, -0.125);
  states[0].b_g = Eigen::Vector3d(1e-4, -2e-4, 3e-4);
  states[0].b_a = Eigen::Vector3d(0.06, 0.258, 0.126);
  states[1] = states[0];
  states[1].t_ns = 5'000'005;
  writeGroundTruthStates(dir / "groundtruth_states.csv", states);
  const std::vector<GroundTruthState> read = readGroundTruthStates(dir / "groundtruth_states.csv");
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[1].t_ns, 5'000'005);
  EXPECT_EQ(read[0].p_W_S, states[0].p_W_S);
  EXPECT_LT((read[0].q_W_S.coeffs() - states[0].q_W_S.coeffs()).norm(), 1e-15);
  EXPECT_EQ(read[0].v_W_S, states[0].v_W_S);
  EXPECT_EQ(read[0].b_g, states[0].b_g);
  EXPECT_EQ(read[0].b_a, states[0].b_a);
}

TEST(GroundTruthStates, RejectsReorderedHeaderAndNonUnitQuaternion) {
  TempDir dir;
  writeText(dir / "s.csv",
            "#t_ns,p_W_S_x,p_W_S_y,p_W_S_z,q_W_S_w,q_W_S_x,q_W_S_y,q_W_S_z,v_W_S_x,v_W_S_y,v_W_S_z,"
            "b_g_x,b_g_y,b_g_z,b_a_x,b_a_y,b_a_z\n");
  expectError([&] { readGroundTruthStates(dir / "s.csv"); },
              "s.csv line 1: header column 5 is 'q_W_S_w', expected 'q_W_S_x'");
  const std::string header =
      "#t_ns,p_W_S_x,p_W_S_y,p_W_S_z,q_W_S_x,q_W_S_y,q_W_S_z,q_W_S_w,v_W_S_x,v_W_S_y,v_W_S_z,"
      "b_g_x,b_g_y,b_g_z,b_a_x,b_a_y,b_a_z\n";
  writeText(dir / "q.csv", header + "1,0,0,0,0,0,0,1.1,0,0,0,0,0,0,0,0,0\n");
  expectError([&] { readGroundTruthStates(dir / "q.csv"); },
              "q.csv line 2: quaternion norm 1.1 is more than 0.001 from 1");
  writeText(dir / "m.csv", header + "1,0,0,0,0,0,0,1,0,0,0,0,0,0,0,0\n");
  expectError([&] { readGroundTruthStates(dir / "m.csv"); },
              "m.csv line 2: column 'b_a_z' is missing (16 of 17 columns)");
}

}  // namespace
}  // namespace vifusion::datasets::test
