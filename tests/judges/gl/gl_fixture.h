// The fixture of every test that needs the OSMesa context: skips (with the reason) when none can
// be made, so a machine without Mesa reports skipped tests rather than failures.
#pragma once
#include <gtest/gtest.h>

#include "gl_context.h"

namespace ahd_test {

class GlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    if (!ensure_gl_context(&why)) GTEST_SKIP() << why;
  }
};

}  // namespace ahd_test
