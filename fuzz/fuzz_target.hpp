// fuzz/fuzz_target.hpp -- the body of both libFuzzer targets: decode the input, check the
// contract, report a violation.
//
// A violation prints the pair as a `tetia pairs` line and the message to stderr and aborts, so
// that libFuzzer saves the input as a crash artifact and stops (what scripts/fuzz.sh relies on
// to fail). With TETIA_FUZZ_LOG=FILE set, violations are appended to FILE instead (the line,
// then the message; at most kLogPerKind per kind and process) and fuzzing goes on: a survey
// mode that collects many kinds of violations in one run, e.g. while a kernel is known to
// violate its contract. TETIA_FUZZ_IGNORE=KIND,KIND,... lets a violation pass when every kind in
// its message is listed (e.g. "moments-overflow,vanished-overflow" while those are accepted), so
// that a run stops only on the others; it applies in both modes.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "decode.hpp"
#include "kernel_contract.hpp"

namespace tetia::fuzz {

inline constexpr int kLogPerKind = 3;

inline void report_violation(const std::string& line, const std::string& message) {
  if (const char* log = std::getenv("TETIA_FUZZ_LOG"); log && *log) {
    static std::map<std::string, int> seen;  // libFuzzer runs inputs one at a time
    if (++seen[message_kind(message)] > kLogPerKind) return;
    if (std::FILE* f = std::fopen(log, "a")) {
      std::fprintf(f, "%s\n%s\n", line.c_str(), message.c_str());
      std::fclose(f);
      return;
    }
    std::fprintf(stderr, "tetia fuzz: cannot append to TETIA_FUZZ_LOG=%s\n", log);
  }
  std::fprintf(stderr, "\n==== kernel contract violated\n%s\n%s\n====\n", line.c_str(),
               message.c_str());
  std::abort();
}

/// Whether every kind of violation in message is listed in TETIA_FUZZ_IGNORE (comma-separated;
/// "mismatch" stands for every mismatch[ENTRY], whose names contain commas).
inline bool ignored(const std::string& message) {
  static const std::vector<std::string> list = [] {
    std::vector<std::string> items;
    const char* v = std::getenv("TETIA_FUZZ_IGNORE");
    const std::string all = v ? v : "";
    for (std::size_t start = 0; start <= all.size();) {
      const std::size_t end = std::min(all.find(',', start), all.size());
      if (end > start) items.push_back(all.substr(start, end - start));
      start = end + 1;
    }
    return items;
  }();
  for (const std::string& kind : message_kinds(message)) {
    bool listed = false;
    for (const std::string& item : list)
      listed = listed || kind == item || kind.rfind(item + "[", 0) == 0;
    if (!listed) return false;
  }
  return true;
}

template <std::size_t N>
int fuzz_one_input(const std::uint8_t* data, std::size_t size) {
  const Coords<N> c = decode<N>(data, size);
  if (const std::string message = check_contract(c); !message.empty() && !ignored(message))
    report_violation(format_line(c), message);
  return 0;
}

}  // namespace tetia::fuzz
