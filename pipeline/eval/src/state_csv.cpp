#include "vifusion/eval/state_csv.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <string_view>

#include "vifusion/core/atomic_file.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::eval {
namespace {

std::vector<std::string_view> splitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    std::string_view field =
        line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    while (!field.empty() && (field.front() == ' ' || field.front() == '\t')) field.remove_prefix(1);
    while (!field.empty() && (field.back() == ' ' || field.back() == '\t' || field.back() == '\r'))
      field.remove_suffix(1);
    fields.push_back(field);
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

/// A CSV table whose first column is an integer time in ns, read with line-precise errors.
class CsvReader {
 public:
  explicit CsvReader(const std::filesystem::path& path) : path_(path), name_(path.filename().string()), in_(path) {
    if (!in_) throw Error(path.string() + ": cannot be read");
    std::string header;
    if (!std::getline(in_, header)) throw Error(name_ + ": empty file, expected a header line");
    ++line_number_;
    if (!header.empty() && header.front() == '#') header.erase(0, 1);
    for (std::string_view column : splitFields(header)) header_.emplace_back(column);
  }

  /// Index of column `name`; throws naming the file and the missing column.
  std::size_t column(const std::string& name) const {
    for (std::size_t i = 0; i < header_.size(); ++i) {
      if (header_[i] == name) return i;
    }
    throw Error(name_ + " line 1: no column '" + name + "' in the header");
  }

  /// Reads the next data row; false at the end of the file.
  bool next() {
    std::string text;
    while (std::getline(in_, text)) {
      ++line_number_;
      if (text.empty() || text == "\r" || text.front() == '#') continue;
      line_ = std::move(text);
      fields_ = splitFields(line_);
      if (fields_.size() < header_.size()) {
        fail("expected " + std::to_string(header_.size()) + " columns, found " + std::to_string(fields_.size()));
      }
      const int64_t t_ns = integerAt(0);
      if (!isFileStampInRange(t_ns)) {
        fail("column '" + header_[0] + "' is beyond the " + std::to_string(kMaxFileStampNs) +
             " ns a stamp may hold: '" + std::string(fields_[0]) + "'");
      }
      if (has_previous_ && t_ns <= previous_t_ns_) {
        char step[64];
        std::snprintf(step, sizeof(step), "%.3f ms", static_cast<double>(previous_t_ns_ - t_ns) * 1e-6);
        fail(t_ns == previous_t_ns_ ? "timestamp repeats the previous line"
                                    : std::string("timestamp goes backwards by ") + step);
      }
      previous_t_ns_ = t_ns;
      has_previous_ = true;
      return true;
    }
    return false;
  }

  int64_t integerAt(std::size_t index) const {
    const std::string_view field = fields_[index];
    int64_t value = 0;
    const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
    if (error != std::errc() || end != field.data() + field.size()) {
      fail("column '" + header_[index] + "' is not an integer: '" + std::string(field) + "'");
    }
    return value;
  }

  double numberAt(std::size_t index) const {
    const std::string field(fields_[index]);
    char* end = nullptr;
    const double value = std::strtod(field.c_str(), &end);
    if (field.empty() || end != field.c_str() + field.size() || !std::isfinite(value)) {
      fail("column '" + header_[index] + "' is not a finite number: '" + field + "'");
    }
    return value;
  }

  /// Indices of the columns <prefix>x, <prefix>y, <prefix>z, each looked up by name.
  std::array<std::size_t, 3> vectorColumns(const std::string& prefix) const {
    return {column(prefix + "x"), column(prefix + "y"), column(prefix + "z")};
  }

  Eigen::Vector3d vectorAt(const std::array<std::size_t, 3>& columns) const {
    return {numberAt(columns[0]), numberAt(columns[1]), numberAt(columns[2])};
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(name_ + " line " + std::to_string(line_number_) + ": " + what);
  }

 private:
  std::filesystem::path path_;
  std::string name_;
  std::ifstream in_;
  std::vector<std::string> header_;
  std::string line_;
  std::vector<std::string_view> fields_;
  std::size_t line_number_ = 0;
  int64_t previous_t_ns_ = 0;
  bool has_previous_ = false;
};

/// states.csv: the header, then one row per record (state_csv.hpp).
void printStates(std::FILE* file, std::span<const StateRecord> records) {
  static constexpr const char* kDeltaNames[kStateDim] = {
      "dr_x",   "dr_y",   "dr_z",   "dalpha_x", "dalpha_y", "dalpha_z", "dv_x", "dv_y", "dv_z",
      "db_g_x", "db_g_y", "db_g_z", "db_a_x",   "db_a_y",   "db_a_z",   "dg_x", "dg_y", "dg_z"};
  std::fprintf(file,
               "#t_ns,r_W_C_x,r_W_C_y,r_W_C_z,q_W_C_x,q_W_C_y,q_W_C_z,q_W_C_w,v_W_S_x,v_W_S_y,v_W_S_z,"
               "b_g_x,b_g_y,b_g_z,b_a_x,b_a_y,b_a_z,g_W_x,g_W_y,g_W_z,q_I_W_x,q_I_W_y,q_I_W_z,q_I_W_w");
  for (const char* name : kDeltaNames) std::fprintf(file, ",var_%s", name);
  std::fprintf(file, "\n");
  const auto put = [&](const auto& vector) {
    for (Eigen::Index i = 0; i < vector.size(); ++i) std::fprintf(file, ",%.17g", vector[i]);
  };
  for (const StateRecord& record : records) {
    const NavState& x = record.x;
    std::fprintf(file, "%lld", static_cast<long long>(record.t_ns));
    put(x.r_W_C);
    put(x.q_W_C.coeffs());
    put(x.q_I_W.conjugate() * x.v_I_S);
    put(x.b_g);
    put(x.b_a);
    put(x.q_I_W.conjugate() * Eigen::Vector3d(0.0, 0.0, -1.0));
    put(x.q_I_W.coeffs());
    put(record.variance);
    std::fprintf(file, "\n");
  }
}

}  // namespace

std::vector<EstimatedState> readEstimatedStates(const std::filesystem::path& path) {
  CsvReader reader(path);
  const std::size_t t = reader.column("t_ns");
  const auto v = reader.vectorColumns("v_W_S_");
  const auto bg = reader.vectorColumns("b_g_");
  const auto ba = reader.vectorColumns("b_a_");
  const auto g = reader.vectorColumns("g_W_");
  std::vector<EstimatedState> states;
  while (reader.next()) {
    EstimatedState state;
    state.t_ns = reader.integerAt(t);
    state.v_W_S = reader.vectorAt(v);
    state.b_g = reader.vectorAt(bg);
    state.b_a = reader.vectorAt(ba);
    state.g_W = reader.vectorAt(g);
    states.push_back(state);
  }
  if (states.empty()) throw Error(path.filename().string() + ": no rows");
  return states;
}

void writeEstimatedStates(const std::filesystem::path& path, std::span<const StateRecord> records) {
  printFileAtomically(path, [&](std::FILE* file) { printStates(file, records); });
}

}  // namespace vifusion::eval
