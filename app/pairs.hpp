// app/pairs.hpp -- `tetia pairs`: intersection volumes of tetrahedron pairs (or areas of
// triangle pairs, dimension 2) read from a stream.
//
// Input: one pair per line, 24 numbers (U's four vertices x y z, then V's) or, in dimension 2,
// 12 numbers (A's three vertices x y, then B's), separated by blanks; blank lines and '#'
// comment lines are skipped. Output: one line per pair, either the volume or area ("%.17g") or
// a JSON object. The first malformed line stops the run: everything before it has
// been written and flushed, then "tetia: line N: <what>" goes to the error stream.
#pragma once

#include <cstdio>
#include <optional>
#include <string_view>

namespace tetia::app {

enum class Algorithm { tetia, clip, pang, exact };
enum class Format { volume, json };

/// "tetia", "clip", "pang", "exact".
std::string_view algorithm_name(Algorithm a);
std::optional<Algorithm> parse_algorithm(std::string_view name);
/// "volume", "json".
std::string_view format_name(Format f);
std::optional<Format> parse_format(std::string_view name);

struct PairsOptions {
  Algorithm algorithm = Algorithm::tetia;
  Format format = Format::volume;
  int dimension = 3;  ///< 3: tetrahedra, 2: triangles
};

/// Exit codes of run_pairs (and of the CLI).
inline constexpr int exit_ok = 0;
inline constexpr int exit_failure = 1;      ///< reading or writing failed, or an algorithm threw
inline constexpr int exit_bad_input = 2;    ///< a malformed input line (or a usage error)

/// Reads pairs from `in` until its end, writes one line per pair to `out`, diagnostics to `err`.
/// Returns exit_ok, exit_bad_input (malformed line) or exit_failure.
int run_pairs(const PairsOptions& options, std::FILE* in, std::FILE* out,
              std::FILE* err = stderr);

}  // namespace tetia::app
