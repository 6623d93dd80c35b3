// The bad-input tests' check of an error: one ahd::Error, one line, "<file>: <cause>".
#pragma once
#include <gtest/gtest.h>

#include <exception>
#include <functional>
#include <string>

#include "core/error.h"

namespace ahd_test {

// `call` must throw one ahd::Error of one line starting with "<file>: " and containing `cause`.
inline void expect_file_error(const std::function<void()>& call, const std::string& file, const std::string& cause) {
  try {
    call();
    ADD_FAILURE() << "accepted; expected '" << cause << "'";
  } catch (const ahd::Error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(file + ": ", 0), 0u) << "does not start with the file: " << m;
    EXPECT_NE(m.find(cause), std::string::npos) << "expected '" << cause << "' in: " << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an ahd::Error: " << e.what();
  }
}

}  // namespace ahd_test
