#include "vifusion/datasets/ground_truth_states.hpp"

#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "text_fields.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::datasets {
namespace {

constexpr std::array<std::string_view, 17> kColumns = {"t_ns",    "p_W_S_x", "p_W_S_y", "p_W_S_z", "q_W_S_x", "q_W_S_y",
                                                       "q_W_S_z", "q_W_S_w", "v_W_S_x", "v_W_S_y", "v_W_S_z", "b_g_x",
                                                       "b_g_y",   "b_g_z",   "b_a_x",   "b_a_y",   "b_a_z"};

// The simulator writes unit quaternions with 17 digits; a larger error is a corrupt row.
constexpr double kMaxQuaternionNormError = 1e-3;

}  // namespace

std::vector<GroundTruthState> readGroundTruthStates(const std::filesystem::path& path) {
  const std::string file = path.filename().string();
  const std::string text = detail::readTextFile(path, file);
  std::vector<GroundTruthState> states;
  bool have_header = false;
  detail::forEachLine(text, [&](std::size_t line_number, std::string_view line) {
    const std::string prefix = detail::where(file, line_number);
    if (line.find_first_not_of(" \t\r") == std::string_view::npos) return;
    if (!have_header) {
      if (line.front() != '#') throw Error(prefix + "expected the header '#t_ns,p_W_S_x,...' before the data");
      const std::vector<std::string_view> names = detail::splitCsv(line.substr(1));
      for (std::size_t c = 0; c < kColumns.size(); ++c) {
        if (c >= names.size()) throw Error(prefix + "header lacks column '" + std::string(kColumns[c]) + "'");
        if (names[c] != kColumns[c]) {
          throw Error(prefix + "header column " + std::to_string(c + 1) + " is '" + std::string(names[c]) +
                      "', expected '" + std::string(kColumns[c]) + "'");
        }
      }
      have_header = true;
      return;
    }
    if (detail::isCommentOrBlank(line)) return;
    const std::vector<std::string_view> fields = detail::splitCsv(line);
    for (std::size_t c = 0; c < kColumns.size(); ++c) {
      if (c >= fields.size() || fields[c].empty()) {
        throw Error(prefix + "column '" + std::string(kColumns[c]) + "' is missing (" + std::to_string(fields.size()) +
                    " of 17 columns)");
      }
    }
    std::array<double, 17> v{};
    for (std::size_t c = 1; c < kColumns.size(); ++c) v[c] = detail::parseFinite(fields[c], prefix, kColumns[c]);
    GroundTruthState state;
    state.t_ns = detail::parseStampNs(fields[0], prefix, kColumns[0]);
    state.p_W_S = Eigen::Vector3d(v[1], v[2], v[3]);
    state.q_W_S = Eigen::Quaterniond(v[7], v[4], v[5], v[6]);
    if (!(std::abs(state.q_W_S.norm() - 1.0) <= kMaxQuaternionNormError)) {
      std::ostringstream message;
      message << prefix << "quaternion norm " << state.q_W_S.norm() << " is more than " << kMaxQuaternionNormError
              << " from 1";
      throw Error(message.str());
    }
    state.q_W_S.normalize();
    state.v_W_S = Eigen::Vector3d(v[8], v[9], v[10]);
    state.b_g = Eigen::Vector3d(v[11], v[12], v[13]);
    state.b_a = Eigen::Vector3d(v[14], v[15], v[16]);
    if (!states.empty()) detail::requireIncreasing(states.back().t_ns, state.t_ns, prefix);
    states.push_back(state);
  });
  if (!have_header) throw Error(file + ": empty file, expected the header '#t_ns,p_W_S_x,...'");
  return states;
}

void writeGroundTruthStates(const std::filesystem::path& path, std::span<const GroundTruthState> states) {
  std::ofstream out(path);
  if (!out) throw Error("cannot create '" + path.string() + "'");
  out.precision(17);
  for (std::size_t c = 0; c < kColumns.size(); ++c) out << (c == 0 ? "#" : ",") << kColumns[c];
  out << '\n';
  for (const GroundTruthState& s : states) {
    const Eigen::Quaterniond& q = s.q_W_S;
    out << s.t_ns;
    for (const double value :
         {s.p_W_S.x(), s.p_W_S.y(), s.p_W_S.z(), q.x(), q.y(), q.z(), q.w(), s.v_W_S.x(), s.v_W_S.y(), s.v_W_S.z(),
          s.b_g.x(), s.b_g.y(), s.b_g.z(), s.b_a.x(), s.b_a.y(), s.b_a.z()}) {
      out << ',' << value;
    }
    out << '\n';
  }
  if (!out.flush()) throw Error("cannot write '" + path.string() + "'");
}

}  // namespace vifusion::datasets
