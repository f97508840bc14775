#include "vifusion/datasets/euroc_imu.hpp"

#include <array>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "text_fields.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::datasets {
namespace {

using detail::where;

constexpr std::array<std::string_view, 7> kColumns = {"timestamp", "w_RS_S_x", "w_RS_S_y", "w_RS_S_z",
                                                      "a_RS_S_x",  "a_RS_S_y", "a_RS_S_z"};

/// Position of each wanted column in a row.
using ColumnIndex = std::array<std::size_t, kColumns.size()>;

// "w_RS_S_x [rad s^-1]" → "w_RS_S_x": the unit text varies between EuRoC tools, the name does not.
std::string_view columnName(std::string_view header_field) {
  const std::size_t bracket = header_field.find('[');
  std::string_view name = header_field.substr(0, bracket);
  while (!name.empty() && name.back() == ' ') name.remove_suffix(1);
  return name;
}

/// One data row; throws vifusion::Error naming file, line and column.
ImuSample readRow(std::string_view line, const std::string& prefix, const ColumnIndex& index,
                  std::size_t header_columns, const std::vector<ImuSample>& samples) {
  const std::vector<std::string_view> fields = detail::splitCsv(line);
  for (std::size_t c = 0; c < kColumns.size(); ++c) {
    if (index[c] >= fields.size() || fields[index[c]].empty()) {
      throw Error(prefix + "column '" + std::string(kColumns[c]) + "' is missing (" + std::to_string(fields.size()) +
                  " of " + std::to_string(header_columns) + " columns)");
    }
  }
  ImuSample sample;
  sample.t_ns = detail::parseStampNs(fields[index[0]], prefix, kColumns[0]);
  for (int axis = 0; axis < 3; ++axis) {
    sample.gyro_rad_s[axis] = detail::parseFinite(fields[index[1 + axis]], prefix, kColumns[1 + axis]);
    sample.accel_mps2[axis] = detail::parseFinite(fields[index[4 + axis]], prefix, kColumns[4 + axis]);
  }
  if (!samples.empty()) detail::requireIncreasing(samples.back().t_ns, sample.t_ns, prefix);
  return sample;
}

}  // namespace

std::vector<ImuSample> readEurocImu(const std::filesystem::path& path, std::vector<std::string>* skipped_rows) {
  const std::string file = path.filename().string();
  const std::string text = detail::readTextFile(path, file);
  std::vector<ImuSample> samples;
  ColumnIndex index{};
  std::size_t header_columns = 0;
  detail::forEachLine(text, [&](std::size_t line_number, std::string_view line) {
    const std::string prefix = where(file, line_number);
    if (header_columns == 0) {
      if (line.find_first_not_of(" \t\r") == std::string_view::npos) return;
      if (line.empty() || line.front() != '#') {
        throw Error(prefix + "expected the header '#timestamp [ns],w_RS_S_x [rad s^-1],...' before the data");
      }
      const std::vector<std::string_view> names = detail::splitCsv(line.substr(1));
      for (std::size_t c = 0; c < kColumns.size(); ++c) {
        std::size_t k = 0;
        while (k < names.size() && columnName(names[k]) != kColumns[c]) ++k;
        if (k == names.size()) throw Error(prefix + "header lacks column '" + std::string(kColumns[c]) + "'");
        index[c] = k;
      }
      header_columns = names.size();
      return;
    }
    if (detail::isCommentOrBlank(line)) return;
    try {
      samples.push_back(readRow(line, prefix, index, header_columns, samples));
    } catch (const Error& error) {
      if (skipped_rows == nullptr) throw;
      skipped_rows->push_back(error.what());
    }
  });
  if (header_columns == 0) throw Error(file + ": empty file, expected the EuRoC header '#timestamp [ns],...'");
  return samples;
}

void writeEurocImu(const std::filesystem::path& path, std::span<const ImuSample> samples) {
  std::ofstream out(path);
  if (!out) throw Error("cannot create '" + path.string() + "'");
  out.precision(17);
  out << "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
         "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n";
  for (const ImuSample& s : samples) {
    out << s.t_ns << ',' << s.gyro_rad_s.x() << ',' << s.gyro_rad_s.y() << ',' << s.gyro_rad_s.z() << ','
        << s.accel_mps2.x() << ',' << s.accel_mps2.y() << ',' << s.accel_mps2.z() << '\n';
  }
  if (!out.flush()) throw Error("cannot write '" + path.string() + "'");
}

}  // namespace vifusion::datasets
