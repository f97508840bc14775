#pragma once
// EuRoC MAV IMU csv (imu0/data.csv; also imu.csv in our dataset directories):
//   #timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],a_RS_S_y [m
//   s^-2],a_RS_S_z [m s^-2] 1403715273262142976,-0.0020943951023931952,...
// Gyro in rad/s and accelerometer (specific force) in m/s², both in the IMU frame S.

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "vifusion/core/sensor_data.hpp"

namespace vifusion::datasets {

/// Reads an EuRoC IMU csv. The '#' header is required and columns are found by name (the unit in
/// brackets is ignored), so a file with reordered or extra columns still reads correctly.
/// @throws vifusion::Error naming the file and line: header missing or lacking a column, a row with
/// too few columns, a non-numeric/NaN/inf value ("imu.csv line 4: column 'w_RS_S_y' is not a
/// number: 'nan'"), a timestamp that does not strictly increase.
/// With `skipped_rows`, a data row that cannot be read is left out and its error appended there instead
/// (the header and the file itself must still be sound).
std::vector<ImuSample> readEurocImu(const std::filesystem::path& path,
                                    std::vector<std::string>* skipped_rows = nullptr);

/// Writes samples in the EuRoC layout with 17 significant digits, so readEurocImu returns them bit-exact.
/// @throws vifusion::Error if the file cannot be written.
void writeEurocImu(const std::filesystem::path& path, std::span<const ImuSample> samples);

}  // namespace vifusion::datasets
