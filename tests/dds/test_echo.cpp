// echo's failures in one process: unknown topics, timeouts, invalid options. Receiving is tested with
// the publisher in another process (test_two_process.cpp), since echo owns its participant.

#include <gtest/gtest.h>

#include <string>

#include "dds_test_support.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/dds/echo.hpp"

namespace vifusion::dds {
namespace {

struct EchoRun {
  int code;
  std::string out;
  std::string err;
};

EchoRun runEcho(const EchoOptions& options) {
  std::FILE* out = std::tmpfile();
  ::testing::internal::CaptureStderr();
  const int code = echo(options, out);
  const std::string err = ::testing::internal::GetCapturedStderr();
  std::string text;
  std::rewind(out);
  for (int c = std::fgetc(out); c != EOF; c = std::fgetc(out)) text += static_cast<char>(c);
  std::fclose(out);
  return {code, text, err};
}

EchoOptions echoOptions(const std::string& topic) {
  EchoOptions options;
  options.topic = topic;
  options.participant = test::loopbackOptions();
  options.count = 1;
  options.timeout_ns = 300 * kNsPerMillisecond;
  return options;
}

TEST(DdsEcho, UnknownTopicNamesTheKnownOnes) {
  const EchoRun run = runEcho(echoOptions("/vifusion/odometri"));
  EXPECT_EQ(run.code, kEchoFailed);
  EXPECT_EQ(run.out, "");
  EXPECT_NE(run.err.find("vifusion echo: unknown topic '/vifusion/odometri' (DDS 'rt/vifusion/odometri')"),
            std::string::npos)
      << run.err;
  EXPECT_NE(run.err.find("rt/vifusion/odometry"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("rt/diagnostics"), std::string::npos) << run.err;
}

TEST(DdsEcho, TimeoutSaysWhatArrived) {
  const EchoRun run = runEcho(echoOptions("/vifusion/odometry"));
  EXPECT_EQ(run.code, kEchoTimedOut);
  EXPECT_EQ(run.out, "");
  EXPECT_NE(run.err.find("vifusion echo: received 0 of 1 samples on 'rt/vifusion/odometry' within 0.3"),
            std::string::npos)
      << run.err;
  EXPECT_NE(run.err.find("writers matched: 0"), std::string::npos) << run.err;
}

TEST(DdsEcho, NoCountAndNothingReceivedIsATimeout) {
  EchoOptions options = echoOptions("rt/vifusion/status");
  options.count = 0;
  const EchoRun run = runEcho(options);
  EXPECT_EQ(run.code, kEchoTimedOut);
  EXPECT_NE(run.err.find("received 0 samples on 'rt/vifusion/status'"), std::string::npos) << run.err;
}

TEST(DdsEcho, InvalidOptionsFail) {
  EchoOptions options = echoOptions("/vifusion/pose");
  options.timeout_ns = -1;
  EchoRun run = runEcho(options);
  EXPECT_EQ(run.code, kEchoFailed);
  EXPECT_NE(run.err.find("'timeout_ns' = -1"), std::string::npos) << run.err;

  options = echoOptions("");
  run = runEcho(options);
  EXPECT_EQ(run.code, kEchoFailed);
  EXPECT_NE(run.err.find("'topic' is empty"), std::string::npos) << run.err;

  options = echoOptions("/vifusion/pose");
  options.participant.config = "/nonexistent.xml";
  run = runEcho(options);
  EXPECT_EQ(run.code, kEchoFailed);
  EXPECT_NE(run.err.find("no Cyclone configuration file '/nonexistent.xml'"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace vifusion::dds
