// tests/support/error_of.hpp -- the message of the exception a call throws, for tests of
// error messages ("tetia: FILE: line 12: ...").
#pragma once

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace tetia::testsupport {

/// The message of the exception of type Error (std::runtime_error unless given; any
/// std::exception with error_of<std::exception>) that `f` throws; fails the test if it throws
/// nothing of that type.
template <class Error = std::runtime_error, class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no exception of the expected type thrown";
  return "";
}

}  // namespace tetia::testsupport
