// tests/support/error_of.hpp -- the message of the std::runtime_error a call throws, for tests of
// error messages ("tetia: FILE: line 12: ...").
#pragma once

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace tetia::testsupport {

/// The message of the std::runtime_error `f` throws; fails the test if it throws nothing.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no std::runtime_error thrown";
  return "";
}

}  // namespace tetia::testsupport
