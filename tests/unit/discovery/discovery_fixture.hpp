#pragma once
// A fresh umockdev test bed per test, and a check for the DiscoveryError a call must throw.

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "vifusion/discovery/discovery_error.hpp"
#include "zr300_testbed.hpp"

namespace vifusion::discovery::test {

class DiscoveryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // Without the preload library libudev would read the machine's real /sys (and find no camera).
    ASSERT_TRUE(umockdevPreloaded()) << "run under umockdev-wrapper (ctest does: CROSSCOMPILING_EMULATOR)";
    testbed_ = std::make_unique<Zr300Testbed>();
  }
  void TearDown() override { testbed_.reset(); }

  Zr300Testbed& testbed() { return *testbed_; }
  /// Removes the test bed now (a death test's child, which exits without tearing down, calls it).
  void destroyTestbed() { testbed_.reset(); }

 private:
  std::unique_ptr<Zr300Testbed> testbed_;
};

/// Runs `call`, which must throw DiscoveryError with `problem` and a message containing `fragment`;
/// returns the message.
template <class Call>
std::string expectProblem(Call&& call, DiscoveryProblem problem, const std::string& fragment) {
  try {
    call();
  } catch (const DiscoveryError& error) {
    EXPECT_EQ(problemName(error.problem()), problemName(problem)) << error.what();
    EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos)
        << "message: " << error.what() << "\nexpected to contain: " << fragment;
    return error.what();
  }
  ADD_FAILURE() << "no DiscoveryError thrown; expected " << problemName(problem);
  return {};
}

}  // namespace vifusion::discovery::test
