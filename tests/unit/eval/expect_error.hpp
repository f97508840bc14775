#pragma once
#include "vifusion/test/expect_error.hpp"

namespace vifusion::eval::test {

using vifusion::test::expectError;

}  // namespace vifusion::eval::test
