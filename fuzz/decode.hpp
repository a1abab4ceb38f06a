// fuzz/decode.hpp -- turning fuzzer bytes (or a text line) into the coordinates of a pair of
// tetrahedra (24 doubles) or triangles (12 doubles), for the fuzz targets, fuzz_replay and
// tests/test_fuzz_regressions.cpp.
//
// Why not just reinterpret the bytes as doubles: random bit patterns are almost always pairs of
// wildly different magnitudes far apart, so the kernels' interesting cases (shared vertices,
// coplanar faces, corners on edges, nearly degenerate and extreme-scale but well-shaped pairs)
// would practically never be reached. The first byte therefore chooses a mode, and the rest are
// that mode's parameters:
//
//   Raw            8 bytes per double; a non-finite pattern keeps its sign and mantissa and gets
//                  the exponent of 1 (so every input decodes to finite doubles).
//   SmallInt       integers in [-r, r], r in 1..8: shared vertices and coplanar faces galore.
//   Dyadic         int8 * 2^-s, s in 0..63: exact grids at any resolution.
//   Nudge          a base pair (below) with up to N coordinates moved by +-127 ulps, or by
//                  +-127 * 2^24 ulps (a relative 1e-9): nearly degenerate pairs; a nudged zero
//                  becomes a subnormal.
//   Scale          a base pair times 2^k, k in [-1070, 1000] (the same k for all coordinates;
//                  near the ends the coordinates themselves round to subnormals or grow to
//                  about 1e301, up to 2^1007 for a dyadic base).
//   Translate      a base pair plus a common offset, each component +-(1 + m/2^16) 2^e with
//                  e in 0..59 (up to 2^60): cancellation in every difference.
//   HugeVertex     a base pair with one vertex replaced by one of magnitude up to 2^997
//                  (about 1e300), or down to 2^-1074: mixed magnitudes within one pair.
//   MixedMagnitude every coordinate with its own exponent in [-1074, 996].
//   Composite      a base pair, nudged, then scaled, then translated.
//
// A base pair is one of a few well-shaped hand-made pairs (identical, shifted, sharing a face,
// disjoint, reflected, tiny inside big, generic), or small integers or a dyadic grid read from
// the bytes. Bytes past the end read as zero, so every input, even an empty one, decodes to a
// well-defined pair: what the fuzzer mutates is always meaningful.
//
// The same pairs can also be written as a text line (format_line) and read back (parse_line):
// the numbers with 17 significant digits, which round-trip every double exactly (subnormals and
// -0 included), in the format of `tetia pairs` (3D) and `tetia pairs --dim 2` (2D).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>

#include "tetia/geometry.hpp"

namespace tetia::fuzz {

/// Coordinates of a pair: 24 for two tetrahedra (3D), 12 for two triangles (2D).
template <std::size_t N>
using Coords = std::array<double, N>;
inline constexpr std::size_t kTetCoords = 24;
inline constexpr std::size_t kTriCoords = 12;
using TetCoords = Coords<kTetCoords>;
using TriCoords = Coords<kTriCoords>;

inline void split(const TetCoords& c, Tet& U, Tet& V) {
  for (int t = 0; t < 2; ++t)
    for (int v = 0; v < 4; ++v)
      for (int a = 0; a < 3; ++a) {
        const double x = c[static_cast<std::size_t>(12 * t + 3 * v + a)];
        (t == 0 ? U : V)[static_cast<std::size_t>(v)][a] = x;
      }
}

inline void split(const TriCoords& c, Triangle& A, Triangle& B) {
  for (int t = 0; t < 2; ++t)
    for (int v = 0; v < 3; ++v) {
      const auto i = static_cast<std::size_t>(6 * t + 2 * v);
      (t == 0 ? A : B)[static_cast<std::size_t>(v)] = Vec2{c[i], c[i + 1]};
    }
}

namespace detail {

/// Reads the input front to back; past the end it yields zeros (see the header comment).
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : p_(data), n_(size) {}

  std::uint8_t u8() {
    if (n_ == 0) return 0;
    --n_;
    return *p_++;
  }
  std::int8_t i8() { return static_cast<std::int8_t>(u8()); }
  std::uint16_t u16() {
    const unsigned lo = u8();  // two statements: the order of the reads must not depend on
    const unsigned hi = u8();  // the compiler's order of evaluation
    return static_cast<std::uint16_t>(lo | (hi << 8));
  }
  std::uint64_t u64() {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= std::uint64_t{u8()} << (8 * i);
    return v;
  }
  /// An integer in [lo, hi] (hi - lo < 2^16).
  int in_range(int lo, int hi) {
    return lo + static_cast<int>(u16() % static_cast<unsigned>(hi - lo + 1));
  }

 private:
  const std::uint8_t* p_;
  std::size_t n_;
};

/// A finite double from any bit pattern: infinities and NaNs keep sign and mantissa and get the
/// exponent of 1.0, i.e. a value in [1, 2) in magnitude.
inline double finite_from_bits(std::uint64_t bits) {
  constexpr std::uint64_t exp_mask = 0x7ff0000000000000ull;
  if ((bits & exp_mask) == exp_mask) bits = (bits & ~exp_mask) | 0x3ff0000000000000ull;
  return std::bit_cast<double>(bits);
}

/// x moved by k ulps through the ordered sequence of doubles (crossing zero and the subnormals
/// like any other spacing), saturating at +-DBL_MAX so the result stays finite.
inline double nudge_ulps(double x, std::int64_t k) {
  const auto bits = std::bit_cast<std::int64_t>(x);
  // Doubles ordered as integers: positive ones by their bits, negative ones mirrored.
  std::int64_t key = bits >= 0 ? bits : -(bits & std::numeric_limits<std::int64_t>::max());
  constexpr auto max_key = std::bit_cast<std::int64_t>(std::numeric_limits<double>::max());
  key = std::clamp<std::int64_t>(key + k, -max_key, max_key);
  return key >= 0 ? std::bit_cast<double>(key)
                  : std::bit_cast<double>(-key | std::numeric_limits<std::int64_t>::min());
}

/// Hand-made well-shaped pairs (coordinates within [-1.25, 1.25], so that Scale up to 2^1000
/// stays finite): the families of examples/pairs.txt and tests/support that a mutation most easily
/// turns into a degenerate neighbour.
inline constexpr std::array<TetCoords, 8> kTetBases = {{
    // identical reference tetrahedra
    {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1},
    // V = U + (1/4, 1/4, 1/4)
    {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1,
     .25, .25, .25, 1.25, .25, .25, .25, 1.25, .25, .25, .25, 1.25},
    // shared face (touching: volume 0)
    {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1},
    // disjoint
    {0, 0, 0, .5, 0, 0, 0, .5, 0, 0, 0, .5, 1, 0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1},
    // the two tetrahedra of the stella octangula (V = -U), opposite orientations
    {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1, -1, -1, -1, -1, 1, 1, 1, -1, 1, 1, 1, -1},
    // tiny inside big
    {-1, -1, -1, 1, -1, -1, 0, 1, -1, 0, 0, 1,
     0, 0, 0, 0x1p-20, 0, 0, 0, 0x1p-20, 0, 0, 0, 0x1p-20},
    // generic overlap, non-dyadic coordinates
    {0.1, 0.2, 0.3, 0.9, 0.1, 0.2, 0.2, 0.8, 0.1, 0.3, 0.3, 0.9,
     0.5, 0.1, 0.1, 0.2, 0.7, 0.3, 0.6, 0.6, 0.7, 0.1, 0.3, 0.6},
    // V = (1,1,1) - U: the two reference corners of the unit cube, overlapping in a double pyramid
    {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1, 0, 1, 1, 1, 0, 1, 1, 1, 0},
}};

inline constexpr std::array<TriCoords, 7> kTriBases = {{
    // identical reference triangles, the second in the other orientation
    {0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0},
    // B = A + (1/4, 1/4)
    {0, 0, 1, 0, 0, 1, .25, .25, 1.25, .25, .25, 1.25},
    // shared edge (touching: area 0)
    {0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 1, 1},
    // star of David
    {0, 1, -0.8660254037844386, -0.5, 0.8660254037844386, -0.5,
     0, -1, 0.8660254037844386, 0.5, -0.8660254037844386, 0.5},
    // tiny inside big
    {-1, -1, 1, -1, 0, 1, 0, 0, 0x1p-20, 0, 0, 0x1p-20},
    // generic overlap, non-dyadic coordinates
    {0.1, 0.2, 0.9, 0.3, 0.4, 0.8, 0.2, 0.7, 0.3, 0.1, 0.7, 0.6},
    // disjoint
    {0, 0, .5, 0, 0, .5, 1, 1, 1, .75, .75, 1},
}};

template <std::size_t N>
constexpr const auto& bases() {
  if constexpr (N == kTetCoords) return kTetBases;
  else return kTriBases;
}

template <std::size_t N>
Coords<N> small_ints(ByteReader& in) {
  const int r = 1 + in.u8() % 8;
  Coords<N> c{};
  for (double& x : c) x = static_cast<int>(in.u8() % static_cast<unsigned>(2 * r + 1)) - r;
  return c;
}

template <std::size_t N>
Coords<N> dyadic(ByteReader& in) {
  const int s = in.u8() % 64;
  Coords<N> c{};
  for (double& x : c) x = std::ldexp(static_cast<double>(in.i8()), -s);
  return c;
}

template <std::size_t N>
Coords<N> base_pair(ByteReader& in) {
  const auto& table = bases<N>();
  const unsigned pick = in.u8() % (table.size() + 2);
  if (pick < table.size()) return table[pick];
  return pick == table.size() ? small_ints<N>(in) : dyadic<N>(in);
}

// +-(1 + m / 2^16) 2^e for the next bytes' sign and m.
inline double signed_power(ByteReader& in, int e) {
  const std::uint16_t m = in.u16();
  const double v = std::ldexp(1.0 + (m >> 1) / 32768.0, e);
  return (m & 1) ? -v : v;
}

template <std::size_t N>
void nudge(ByteReader& in, Coords<N>& c) {
  const unsigned count = in.u8() % (N + 1);
  for (unsigned i = 0; i < count; ++i) {
    const std::uint8_t where = in.u8();
    std::int64_t k = in.i8();
    if (where & 0x80) k *= std::int64_t{1} << 24;
    double& x = c[(where & 0x7f) % N];
    x = nudge_ulps(x, k);
  }
}

template <std::size_t N>
void scale(ByteReader& in, Coords<N>& c) {
  const int k = in.in_range(-1070, 1000);
  for (double& x : c) x = std::ldexp(x, k);
}

template <std::size_t N>
void translate(ByteReader& in, Coords<N>& c) {
  constexpr std::size_t dim = N == kTetCoords ? 3 : 2;
  double t[dim];
  for (double& ti : t) ti = signed_power(in, in.u8() % 60);
  for (std::size_t i = 0; i < N; ++i) c[i] += t[i % dim];
}

}  // namespace detail

enum class Mode : std::uint8_t {
  Raw, SmallInt, Dyadic, Nudge, Scale, Translate, HugeVertex, MixedMagnitude, Composite, Count
};

/// The pair encoded by a fuzzer input (see the header comment). Every coordinate is finite.
template <std::size_t N>
Coords<N> decode(const std::uint8_t* data, std::size_t size) {
  static_assert(N == kTetCoords || N == kTriCoords);
  using namespace detail;
  ByteReader in(data, size);
  constexpr std::size_t dim = N == kTetCoords ? 3 : 2;
  const auto mode = static_cast<Mode>(in.u8() % static_cast<unsigned>(Mode::Count));
  Coords<N> c{};
  switch (mode) {
    case Mode::Raw:
      for (double& x : c) x = finite_from_bits(in.u64());
      break;
    case Mode::SmallInt:
      c = small_ints<N>(in);
      break;
    case Mode::Dyadic:
      c = dyadic<N>(in);
      break;
    case Mode::Nudge:
      c = base_pair<N>(in);
      nudge(in, c);
      break;
    case Mode::Scale:
      c = base_pair<N>(in);
      scale(in, c);
      break;
    case Mode::Translate:
      c = base_pair<N>(in);
      translate(in, c);
      break;
    case Mode::HugeVertex: {
      c = base_pair<N>(in);
      const std::size_t v = in.u8() % (N / dim);
      // Mostly huge (the brief's "one vertex huge, others small"), sometimes tiny.
      const bool tiny = in.u8() % 4 == 0;
      for (std::size_t a = 0; a < dim; ++a) {
        const int e = tiny ? in.in_range(-1074, -900) : in.in_range(0, 996);
        c[v * dim + a] = signed_power(in, e);
      }
      break;
    }
    case Mode::MixedMagnitude:
      for (double& x : c) x = signed_power(in, in.in_range(-1074, 996));
      break;
    case Mode::Composite:
      c = base_pair<N>(in);
      nudge(in, c);
      scale(in, c);
      translate(in, c);
      break;
    case Mode::Count:
      break;  // unreachable: the mode is reduced modulo Count
  }
  // Every step above keeps doubles finite (Scale stays below 2^1008, HugeVertex below 2^997,
  // Translate adds less than 2^60); kept as a guard should a mode be added that does not.
  for (double& x : c)
    if (!std::isfinite(x)) x = finite_from_bits(std::bit_cast<std::uint64_t>(x));
  return c;
}

/// The pair as one line of `tetia pairs` input: 17 significant digits, one vertex per group.
template <std::size_t N>
std::string format_line(const Coords<N>& c) {
  constexpr std::size_t dim = N == kTetCoords ? 3 : 2;
  std::string line;
  char buf[32];
  for (std::size_t i = 0; i < N; ++i) {
    std::snprintf(buf, sizeof buf, "%.17g", c[i]);
    if (i > 0) line += i == N / 2 ? "    " : (i % dim == 0 ? "  " : " ");
    line += buf;
  }
  return line;
}

/// Parses a text line of exactly N finite numbers separated by blanks. Returns false for a
/// line without data (blank or '#' comment) and for a malformed one; error says which (empty
/// for a line without data).
template <std::size_t N>
bool parse_line(std::string_view line, Coords<N>& out, std::string& error) {
  error.clear();
  const auto blank = [](char ch) {
    return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\v' || ch == '\f';
  };
  std::size_t i = 0, count = 0;
  while (i < line.size() && blank(line[i])) ++i;
  if (i == line.size() || line[i] == '#') return false;
  while (i < line.size()) {
    std::size_t j = i;
    while (j < line.size() && !blank(line[j])) ++j;
    const std::string_view field = line.substr(i, j - i);
    // from_chars rejects a leading '+', which %.17g never writes but a hand edit might.
    const std::string_view digits = field.size() > 1 && field[0] == '+' ? field.substr(1) : field;
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    if (ptr != digits.data() + digits.size() || ec == std::errc::invalid_argument) {
      error = "'" + std::string(field) + "' is not a number";
      return false;
    }
    // Underflow (e.g. 1e-400) is reported as out of range too; only overflow is an error.
    if (ec == std::errc::result_out_of_range) v = std::strtod(std::string(digits).c_str(), nullptr);
    if (!std::isfinite(v)) {
      error = "'" + std::string(field) + "' is not finite";
      return false;
    }
    if (count < N) out[count] = v;
    ++count;
    i = j;
    while (i < line.size() && blank(line[i])) ++i;
  }
  if (count != N) {
    error = "expected " + std::to_string(N) + " numbers, got " + std::to_string(count);
    return false;
  }
  return true;
}

}  // namespace tetia::fuzz
