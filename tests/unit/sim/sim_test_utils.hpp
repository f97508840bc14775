#pragma once
// Shared pieces of the simulator tests: reading the ICL-NUIM TUM files (the library leaves file reading to
// its callers) and fitting them as the CLI will.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "vifusion/sim/stamped_pose.hpp"
#include "vifusion/test/data_paths.hpp"

namespace vifusion::sim::test {

/// "t tx ty tz qx qy qz qw" per line, '#' comments; fails the test if the file is missing.
inline std::vector<StampedPose> readIclNuim(int index) {
  const auto path =
      vifusion::test::dataDir() / "icl-nuim-trajectories" / ("livingRoom" + std::to_string(index) + ".tum.txt");
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "cannot open " << path;
  std::vector<StampedPose> poses;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double t_s = 0.0;
    Eigen::Vector3d t_W_m;
    double qx = 0.0, qy = 0.0, qz = 0.0, qw = 1.0;
    fields >> t_s >> t_W_m.x() >> t_W_m.y() >> t_W_m.z() >> qx >> qy >> qz >> qw;
    poses.push_back({std::llround(t_s * 1e9), SE3d(Eigen::Quaterniond(qw, qx, qy, qz), t_W_m)});
  }
  return poses;
}

/// A camera → IMU extrinsic like a real rig's: a few centimetres of lever arm and a small misalignment.
inline SE3d exampleT_S_C() {
  return SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.05, Eigen::Vector3d(0.3, -1.0, 0.2).normalized())),
              Eigen::Vector3d(0.045, -0.012, 0.008));
}

}  // namespace vifusion::sim::test
