#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "expect_error.hpp"
#include "temp_file.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/eval/state_csv.hpp"
#include "vifusion/eval/state_errors.hpp"

namespace vifusion::eval {
namespace {

using test::expectError;
using test::TempFile;

/// 20 s of ground truth at 200 Hz: circular velocity, slowly drifting biases.
std::vector<GroundTruthState> groundTruth() {
  std::vector<GroundTruthState> states;
  for (int k = 0; k <= 4000; ++k) {
    GroundTruthState s;
    s.t_ns = 1'000'000'000 + int64_t{k} * 5'000'000;
    const double t = 0.005 * k;
    s.v_W_S = Eigen::Vector3d(std::cos(t), 0.2, std::sin(t));
    s.b_g = Eigen::Vector3d(0.01, -0.02, 0.005) + 1e-4 * t * Eigen::Vector3d::Ones();
    s.b_a = Eigen::Vector3d(0.1, 0.05, -0.08);
    states.push_back(s);
  }
  return states;
}

TEST(StateErrors, KnownOffsetsInARotatedWorldGiveKnownErrors) {
  const std::vector<GroundTruthState> gt = groundTruth();
  const Eigen::Matrix3d R_gt_est = expSO3(Eigen::Vector3d(0.1, -0.4, 0.3)).toRotationMatrix();
  const Eigen::Vector3d g_gt(0.0, -9.81, 0.0);
  std::vector<EstimatedState> est;
  for (int k = 0; k < 600; ++k) {  // 30 Hz frames, between IMU samples
    EstimatedState e;
    e.t_ns = 1'000'000'000 + int64_t{k} * 33'333'333;
    const double t = 1e-9 * static_cast<double>(e.t_ns - 1'000'000'000);
    e.v_W_S = R_gt_est.transpose() * (Eigen::Vector3d(std::cos(t), 0.2, std::sin(t)) + Eigen::Vector3d(0.03, 0, 0.04));
    e.b_g = Eigen::Vector3d(0.01, -0.02, 0.005) + 1e-4 * t * Eigen::Vector3d::Ones() + Eigen::Vector3d(0, 2e-3, 0);
    e.b_a = Eigen::Vector3d(0.1, 0.05, -0.08) + Eigen::Vector3d(0.03, 0.04, 0);
    // Gravity estimate tilted by exactly 0.5° about x in the ground-truth world.
    e.g_W = R_gt_est.transpose() * (expSO3(Eigen::Vector3d(0.5 * M_PI / 180.0, 0, 0)) * g_gt);
    est.push_back(e);
  }
  const StateErrors errors = stateErrors(gt, est, R_gt_est, g_gt);
  EXPECT_EQ(errors.series.size(), est.size());
  // Ground truth is linear between 5 ms samples; the circle's curvature adds < 1e-5 m/s.
  EXPECT_NEAR(errors.velocity_rms_mps, 0.05, 1e-5);
  EXPECT_NEAR(errors.velocity_rms_after_5s_mps, 0.05, 1e-5);
  EXPECT_NEAR(errors.gyro_bias_max_after_15s, 2e-3, 1e-9);
  EXPECT_NEAR(errors.accel_bias_max_after_15s, 0.05, 1e-9);
  EXPECT_NEAR(errors.gravity_final_deg, 0.5, 1e-9);
  EXPECT_NEAR(errors.gravity_rms_deg, 0.5, 1e-9);
}

TEST(StateErrors, ShortSequencesReportNotANumberForLateWindows) {
  const std::vector<GroundTruthState> gt = groundTruth();
  EstimatedState e;
  e.t_ns = gt[10].t_ns;
  e.g_W = Eigen::Vector3d(0, -1, 0);
  const StateErrors errors = stateErrors(gt, {e}, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, -9.81, 0));
  EXPECT_TRUE(std::isnan(errors.gyro_bias_max_after_15s));
  EXPECT_TRUE(std::isnan(errors.velocity_rms_after_5s_mps));
  EXPECT_NEAR(errors.gravity_final_deg, 0.0, 1e-12);
}

TEST(StateErrors, NoOverlapIsAnError) {
  EstimatedState e;
  e.t_ns = 1;
  expectError([&] { stateErrors(groundTruth(), {e}, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, -9.81, 0)); },
              "no estimated state lies within");
}

TEST(StateCsv, WrittenStatesReadBackInTheWorldFrame) {
  // The writer rotates v_I_S into W by the state's own q_I_W and writes gravity's direction in W; the
  // reader must get exactly those back (17 significant digits).
  StateRecord record;
  record.t_ns = 1'234'567'890'123;
  record.x.r_W_C = Eigen::Vector3d(1.0, -2.0, 0.5);
  record.x.q_W_C = expSO3(Eigen::Vector3d(0.1, 0.2, -0.3));
  record.x.q_I_W = expSO3(Eigen::Vector3d(1.4, 0.1, 0.7));
  record.x.v_I_S = Eigen::Vector3d(0.3, -0.1, 0.05);
  record.x.b_g = Eigen::Vector3d(0.01, -0.02, 0.003);
  record.x.b_a = Eigen::Vector3d(0.1, 0.05, -0.07);
  for (int i = 0; i < kStateDim; ++i) record.variance[i] = 1e-6 * (i + 1);
  StateRecord later = record;
  later.t_ns += 33'333'333;
  const TempFile file("states.csv", "");
  const std::vector<StateRecord> records = {record, later};
  writeEstimatedStates(file.path(), records);
  const std::vector<EstimatedState> read = readEstimatedStates(file.path());
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[1].t_ns, later.t_ns);
  EXPECT_LT((read[0].v_W_S - record.x.q_I_W.conjugate() * record.x.v_I_S).norm(), 1e-15);
  EXPECT_EQ(read[0].b_g, record.x.b_g);
  EXPECT_EQ(read[0].b_a, record.x.b_a);
  // Gravity points down in I; in W it is wherever q_I_W says.
  EXPECT_LT((record.x.q_I_W * read[0].g_W - Eigen::Vector3d(0.0, 0.0, -1.0)).norm(), 1e-15);
  std::ifstream in(file.path());
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(std::count(header.begin(), header.end(), ','), 41);
  EXPECT_NE(header.find(",var_dg_z"), std::string::npos) << header;
  expectError([&] { writeEstimatedStates("/nonexistent/dir/states.csv", records); },
              "/nonexistent/dir/states.csv: cannot create a file in '/nonexistent/dir'");
}

TEST(StateCsv, CorruptTablesNameFileLineAndColumn) {
  const std::string header = "t_ns,v_W_S_x,v_W_S_y,v_W_S_z,b_g_x,b_g_y,b_g_z,b_a_x,b_a_y,b_a_z,g_W_x,g_W_y,g_W_z\n";
  const std::string row = ",0,0,0,0,0,0,0,0,0,0,-1,0\n";
  {
    const TempFile file("states.csv", header + "100" + row + "90" + row);
    expectError([&] { readEstimatedStates(file.path()); }, "states.csv line 3: timestamp goes backwards by 0.000 ms");
  }
  {
    const TempFile file("states.csv", header + "100,0,nan,0,0,0,0,0,0,0,0,-1,0\n");
    expectError([&] { readEstimatedStates(file.path()); }, "line 2: column 'v_W_S_y' is not a finite number: 'nan'");
  }
  {
    const TempFile file("states.csv", "t_ns,v_W_S_x,v_W_S_y,v_W_S_z\n100,0,0,0\n");
    expectError([&] { readEstimatedStates(file.path()); }, "no column 'b_g_x'");
  }
  {
    const TempFile file("states.csv", header + "100,0,0\n");
    expectError([&] { readEstimatedStates(file.path()); }, "line 2: expected 13 columns, found 3");
  }
  {
    const TempFile file("states.csv", header + "1.5" + row);
    expectError([&] { readEstimatedStates(file.path()); }, "column 't_ns' is not an integer: '1.5'");
  }
  {
    const TempFile file("states.csv", header + "-9223372036854775000" + row);
    expectError([&] { readEstimatedStates(file.path()); },
                "line 2: column 't_ns' is beyond the 4000000000000000000 ns a stamp may hold");
  }
  expectError([] { readEstimatedStates("/nonexistent/states.csv"); }, "/nonexistent/states.csv: cannot be read");
}

}  // namespace
}  // namespace vifusion::eval
