// fuzz/inputs.hpp -- reading kept fuzz inputs from files, for fuzz_replay and
// tests/test_fuzz_regressions.cpp.
//
// Two formats, told apart by the file name: a file ending in ".txt" holds text lines of N
// numbers each (`tetia pairs` input: blank and '#' lines skipped, see parse_line); any other file
// is one raw fuzzer input (a corpus entry or a crash artifact), decoded as the fuzz target
// decodes it. Text is the format for regressions taken from reports (it is what a violation
// prints); raw files keep the fuzzer's own inputs, e.g. the seed corpus.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "decode.hpp"

namespace tetia::fuzz {

template <std::size_t N>
struct Case {
  std::string where;  ///< "FILE" for a raw input, "FILE:LINE" for a text line
  Coords<N> coords{};
  std::string error;  ///< why the file or line could not be read (then coords is meaningless)
};

inline bool is_text_input(const std::filesystem::path& file) { return file.extension() == ".txt"; }

/// Every case in file (a text file may hold none).
template <std::size_t N>
std::vector<Case<N>> read_cases(const std::filesystem::path& file) {
  std::vector<Case<N>> cases;
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    cases.push_back({file.string(), {}, "cannot open"});
    return cases;
  }
  if (is_text_input(file)) {
    std::string line, error;
    for (int number = 1; std::getline(in, line); ++number) {
      Case<N> c{file.string() + ":" + std::to_string(number), {}, {}};
      if (parse_line<N>(line, c.coords, error) || !error.empty()) {
        c.error = error;
        cases.push_back(std::move(c));
      }
    }
    return cases;
  }
  const std::vector<char> bytes{std::istreambuf_iterator<char>(in),
                                std::istreambuf_iterator<char>()};
  cases.push_back({file.string(),
                   decode<N>(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()),
                   {}});
  return cases;
}

/// The regular files under dir, recursively, sorted (a missing dir has none). Hidden files
/// (".gitkeep") are skipped.
inline std::vector<std::filesystem::path> input_files(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().filename().string().front() != '.')
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace tetia::fuzz
