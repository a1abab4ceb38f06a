// tests/support/temp_dir.hpp -- a GoogleTest fixture that gives each test an empty folder of its
// own under the system's temporary directory, removed afterwards (TETIA_KEEP_TEST_FILES=1 keeps
// it, to look at the files).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <utility>

namespace tetia::testsupport {

class TempDirTest : public ::testing::Test {
 protected:
  // prefix: names the test file's folders, "tetia_test_PREFIX_PID_SUITE_TEST".
  explicit TempDirTest(std::string prefix) : prefix_(std::move(prefix)) {}

  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() / ("tetia_test_" + prefix_ + "_" + std::to_string(::getpid()) + "_" +
                                                     info->test_suite_name() + "_" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    if (std::getenv("TETIA_KEEP_TEST_FILES") != nullptr) return;
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  std::filesystem::path path(const std::string& name) const { return dir_ / name; }

  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace tetia::testsupport
