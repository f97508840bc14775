// The report as the CLI prints and draws it: one JSON object whose keys are all there and whose values
// parse back to the report's numbers (NaN as null); a PNG of the offsets.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/synccheck/analyse.hpp"
#include "vifusion/synccheck/clock_model.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::synccheck {
namespace {

using nlohmann::json;

TEST(SynccheckJson, KeysArePresentAndValuesParseBack) {
  ClockModel model;
  model.drift_ppm = -120.0;  // one failing check, to see it listed
  const SyncReport report = analyse(simulate(model, 51));
  const std::string text = report.toJson();
  EXPECT_EQ(text.find('\n'), std::string::npos);  // one line
  const json j = json::parse(text);

  for (const char* key : {"passed", "failed_checks", "checks", "frames", "edges", "dropped", "duplicated", "streams",
                          "imu", "clock_mapper", "problems"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["passed"].get<bool>(), false);
  EXPECT_EQ(j["failed_checks"], json::array({"drift"}));
  ASSERT_EQ(j["checks"].size(), report.checks.size());
  EXPECT_EQ(j["checks"][2]["name"], "drift");
  EXPECT_EQ(j["checks"][2]["unit"], "ppm");
  EXPECT_DOUBLE_EQ(j["checks"][2]["value"].get<double>(), report.checks[2].value);
  EXPECT_EQ(j["checks"][2]["passed"].get<bool>(), false);

  for (const StreamStats& s : report.streams) {
    const json& js = j["streams"][s.name];
    EXPECT_EQ(js["count"].get<std::size_t>(), s.count) << s.name;
    EXPECT_DOUBLE_EQ(js["offset_mean_ns"].get<double>(), s.offset_mean_ns);
    EXPECT_DOUBLE_EQ(js["offset_median_ns"].get<double>(), s.offset_median_ns);
    EXPECT_DOUBLE_EQ(js["offset_at_first_ns"].get<double>(), s.offset_at_first_ns);
    EXPECT_DOUBLE_EQ(js["drift_ppm"].get<double>(), s.drift_ppm);
    EXPECT_DOUBLE_EQ(js["jitter_std_ns"].get<double>(), s.jitter_std_ns);
    EXPECT_DOUBLE_EQ(js["jitter_p99_ns"].get<double>(), s.jitter_p99_ns);
    EXPECT_DOUBLE_EQ(js["jitter_max_ns"].get<double>(), s.jitter_max_ns);
  }
  EXPECT_NEAR(j["streams"]["frame_minus_edge"]["drift_ppm"].get<double>(), -120.0, 2.0);
  EXPECT_EQ(j["frames"]["count"].get<std::size_t>(), report.frames.count);
  EXPECT_EQ(j["frames"]["frame_numbers_present"].get<bool>(), true);
  EXPECT_DOUBLE_EQ(j["frames"]["rate_hz"].get<double>(), report.frames.rate_hz);
  EXPECT_EQ(j["edges"]["polarity"], "rising");
  EXPECT_EQ(j["edges"]["used"].get<std::size_t>(), report.edges.used);
  EXPECT_DOUBLE_EQ(j["edges"]["period_ns"].get<double>(), report.edges.period_ns);
  EXPECT_EQ(j["dropped"]["dropped"].get<std::uint64_t>(), report.dropped.dropped);
  EXPECT_DOUBLE_EQ(j["dropped"]["fraction"].get<double>(), report.dropped.fraction);
  EXPECT_EQ(j["duplicated"]["frames_on_one_edge"].get<std::size_t>(), 0u);
  EXPECT_DOUBLE_EQ(j["imu"]["rate_hz"].get<double>(), report.imu.rate_hz);
  EXPECT_DOUBLE_EQ(j["imu"]["largest_gap_ns"].get<double>(), report.imu.largest_gap_ns);
  EXPECT_EQ(j["imu"]["samples"].get<std::size_t>(), report.imu.samples);
  EXPECT_DOUBLE_EQ(j["clock_mapper"]["residual_mean_ns"].get<double>(), report.clock_residuals.mean_ns);
  EXPECT_DOUBLE_EQ(j["clock_mapper"]["residual_p99_abs_ns"].get<double>(), report.clock_residuals.p99_abs_ns);
  EXPECT_TRUE(j["problems"].empty());
}

TEST(SynccheckJson, UnmeasuredValuesAreNull) {
  const json j = json::parse(analyse(SyncInput{}).toJson());
  EXPECT_TRUE(j["streams"]["frame_minus_edge"]["drift_ppm"].is_null());
  EXPECT_TRUE(j["imu"]["rate_hz"].is_null());
  EXPECT_TRUE(j["checks"][0]["value"].is_null());
  EXPECT_EQ(j["checks"][0]["detail"], "no frame paired with a sync edge");
}

TEST(SynccheckPlot, WritesAPng) {
  ClockModel model;
  model.event_probability = 0.9;  // all four streams, kernel-stamped frames among them
  const SyncReport report = analyse(simulate(model, 52));
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "synccheck_plot";
  std::filesystem::create_directories(dir);
  const std::filesystem::path png = dir / "offsets.png";
  std::filesystem::remove(png);
  report.savePlot(png);
  ASSERT_TRUE(std::filesystem::exists(png));
  EXPECT_GT(std::filesystem::file_size(png), 10'000u);  // axes, text and four series, not an empty canvas
  std::ifstream file(png, std::ios::binary);
  std::array<unsigned char, 8> signature{};
  file.read(reinterpret_cast<char*>(signature.data()), signature.size());
  const std::array<unsigned char, 8> kPngSignature{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  EXPECT_EQ(signature, kPngSignature);
}

TEST(SynccheckPlot, AnUnwritablePathIsAnError) {
  const SyncReport report = analyse(simulate(ClockModel{}, 53));
  test::expectError([&] { report.savePlot("/nonexistent-dir/offsets.png"); }, "/nonexistent-dir/offsets.png");
}

}  // namespace
}  // namespace vifusion::synccheck
