#pragma once
// Checks that an action fails with a vifusion::Error whose message says what the user must read.

#include <gtest/gtest.h>

#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::test {

/// Runs `action` and checks it throws vifusion::Error whose message contains `expected`: the message
/// is the user interface of a boundary error, so its wording is part of the contract.
template <typename Action>
void expectError(Action&& action, const std::string& expected) {
  try {
    action();
    ADD_FAILURE() << "no vifusion::Error thrown; expected one containing \"" << expected << "\"";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
        << "message \"" << e.what() << "\" lacks \"" << expected << "\"";
  }
}

}  // namespace vifusion::test
