// tests/support/json_text.hpp -- values read from the one-line JSON objects the CLI prints, by
// key (the first occurrence): enough for the tests' checks, not a JSON parser.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <string_view>

namespace tetia::testjson {

/// The number after "key": (null gives NaN; a missing key fails the test).
inline double json_number(const std::string& json, const std::string& key) {
  const std::string tag = "\"" + key + "\": ";
  const auto at = json.find(tag);
  if (at == std::string::npos) {
    ADD_FAILURE() << "no key " << key << " in " << json;
    return std::nan("");
  }
  const char* p = json.c_str() + at + tag.size();
  if (std::string_view(p, 4) == "null") return std::nan("");
  char* end = nullptr;
  const double v = std::strtod(p, &end);
  EXPECT_NE(end, p) << "no number for " << key << " in " << json;
  return v;
}

/// The string after "key": (empty if there is none).
inline std::string json_string(const std::string& json, const std::string& key) {
  const std::string tag = "\"" + key + "\": \"";
  const auto at = json.find(tag);
  if (at == std::string::npos) return "";
  const auto from = at + tag.size();
  return json.substr(from, json.find('"', from) - from);
}

}  // namespace tetia::testjson
