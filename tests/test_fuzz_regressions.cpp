// test_fuzz_regressions.cpp -- replays the kept fuzz inputs through the fuzzers' own decoding
// and contract (fuzz/decode.hpp, fuzz/kernel_contract.hpp): every file under
// fuzz/corpus/<target>/ (the seeds) and fuzz/regressions/<target>/ (violations found by
// fuzzing, once fixed) must satisfy the contract, in every build the suite runs in, without
// libFuzzer. Files ending in ".txt" hold text lines of numbers (`tetia pairs` format), other
// files are raw fuzzer inputs (fuzz/inputs.hpp).
//
// Also unit tests of the harness itself: the decoder yields finite doubles for any bytes, the
// text format round-trips every double, the exact rounding used by the bounds is correct, and
// the contract does flag what it must (so that an always-empty message cannot pass unnoticed).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "../fuzz/inputs.hpp"
#include "../fuzz/kernel_contract.hpp"
#include "tetia/io.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tetia::fuzz;

// The fuzz directory, found from this file's path (CMake compiles it by absolute path).
const fs::path kFuzzDir = fs::path(__FILE__).parent_path().parent_path() / "fuzz";

template <std::size_t N>
void replay_target(const std::string& target) {
  int seeds = 0;
  for (const char* kind : {"corpus", "regressions"}) {
    for (const fs::path& file : input_files(kFuzzDir / kind / target)) {
      for (const Case<N>& c : read_cases<N>(file)) {
        if (kind == std::string("corpus")) ++seeds;
        ASSERT_TRUE(c.error.empty()) << c.where << ": " << c.error;
        EXPECT_EQ(check_contract(c.coords), "") << c.where << "\n" << format_line(c.coords);
      }
    }
  }
  // A wrong path would otherwise pass with nothing checked.
  EXPECT_GE(seeds, 1) << "no seed inputs under " << (kFuzzDir / "corpus" / target);
}

TEST(FuzzRegressions, TetKernel) { replay_target<kTetCoords>("fuzz_tet_kernel"); }
TEST(FuzzRegressions, TriKernel) { replay_target<kTriCoords>("fuzz_tri_kernel"); }

// The reader's seeds (valid files, each must read) and its findings (each must read or fail
// with a message naming the file), through the public reader.
TEST(FuzzRegressions, MshReader) {
  int seeds = 0;
  for (const char* kind : {"corpus", "regressions"}) {
    for (const fs::path& file : input_files(kFuzzDir / kind / "fuzz_msh_reader")) {
      SCOPED_TRACE(file.string());
      try {
        const tetia::AnyMesh m = tetia::read_any_mesh(file);
        (void)m;
      } catch (const std::runtime_error& e) {
        EXPECT_NE(kind, std::string("corpus")) << e.what();
        EXPECT_EQ(std::string(e.what()).rfind("tetia: " + file.string() + ": ", 0), 0u) << e.what();
      }
      seeds += kind == std::string("corpus");
    }
  }
  EXPECT_GE(seeds, 4) << "no seed files under " << (kFuzzDir / "corpus" / "fuzz_msh_reader");
}

TEST(FuzzHarness, ReadsTextAndRawFiles) {
  const fs::path dir = fs::path(::testing::TempDir()) / "tetia_fuzz_inputs";
  fs::create_directories(dir);
  {
    std::ofstream(dir / "pairs.txt") << "# a comment\n\n0 0 1 0 0 1  0 0 1 0 0 1\n0 0 1\n";
    std::ofstream(dir / "raw", std::ios::binary) << '\x01' << "abc";
  }
  const auto text = read_cases<kTriCoords>(dir / "pairs.txt");
  ASSERT_EQ(text.size(), 2u);
  EXPECT_EQ(text[0].where, (dir / "pairs.txt").string() + ":3");
  EXPECT_TRUE(text[0].error.empty());
  EXPECT_EQ(text[0].coords[2], 1.0);
  EXPECT_EQ(text[1].error, "expected 12 numbers, got 3");
  const auto raw = read_cases<kTriCoords>(dir / "raw");
  ASSERT_EQ(raw.size(), 1u);
  const std::uint8_t bytes[] = {1, 'a', 'b', 'c'};
  EXPECT_EQ(raw[0].coords, decode<kTriCoords>(bytes, sizeof bytes));
  EXPECT_EQ(input_files(dir), (std::vector<fs::path>{dir / "pairs.txt", dir / "raw"}));
  EXPECT_TRUE(input_files(dir / "missing").empty());
  fs::remove_all(dir);
}

TEST(FuzzHarness, DecodeGivesFiniteCoordinatesAndIsDeterministic) {
  std::mt19937_64 rng(12345);
  std::vector<std::uint8_t> bytes;
  for (int i = 0; i < 20000; ++i) {
    bytes.resize(rng() % 220);
    for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
    // Half the inputs cycle through the modes, so that each is decoded often.
    if (i % 2 == 0 && !bytes.empty())
      bytes[0] = static_cast<std::uint8_t>(i / 2 % static_cast<int>(Mode::Count));
    const TetCoords a = decode<kTetCoords>(bytes.data(), bytes.size());
    for (double x : a) ASSERT_TRUE(std::isfinite(x));
    EXPECT_EQ(a, decode<kTetCoords>(bytes.data(), bytes.size()));
    const TriCoords b = decode<kTriCoords>(bytes.data(), bytes.size());
    for (double x : b) ASSERT_TRUE(std::isfinite(x));
  }
  // The format is pinned (kept inputs must decode alike with every compiler): Scale, base pair 1
  // (V = U + 1/4), k = -1070 + 1110 read little-endian.
  const std::uint8_t scale[] = {static_cast<std::uint8_t>(Mode::Scale), 1, 1110 & 0xff, 1110 >> 8};
  const TetCoords scaled = decode<kTetCoords>(scale, sizeof scale);
  EXPECT_EQ(scaled[3], 0x1p40);
  EXPECT_EQ(scaled[12], 0x1p38);
  EXPECT_EQ(scaled[15], 1.25 * 0x1p40);
  // Even a raw NaN or infinity decodes to a finite value.
  std::vector<std::uint8_t> raw(1 + 8 * kTetCoords, 0xff);
  raw[0] = static_cast<std::uint8_t>(Mode::Raw);
  for (double x : decode<kTetCoords>(raw.data(), raw.size())) EXPECT_TRUE(std::isfinite(x));
  EXPECT_EQ(decode<kTriCoords>(nullptr, 0), TriCoords{});  // Raw mode, all bytes zero
}

TEST(FuzzHarness, NudgeUlpsWalksTheDoubles) {
  using detail::nudge_ulps;
  constexpr double tiny = std::numeric_limits<double>::denorm_min();
  constexpr double big = std::numeric_limits<double>::max();
  EXPECT_EQ(nudge_ulps(0.0, 1), tiny);
  EXPECT_EQ(nudge_ulps(0.0, -2), -2 * tiny);
  EXPECT_EQ(nudge_ulps(tiny, -3), -2 * tiny);
  EXPECT_EQ(nudge_ulps(1.0, 1), std::nextafter(1.0, 2.0));
  EXPECT_EQ(nudge_ulps(-1.0, 1), std::nextafter(-1.0, 0.0));
  EXPECT_EQ(nudge_ulps(big, 5), big);
  EXPECT_EQ(nudge_ulps(-big, -5), -big);
}

TEST(FuzzHarness, TextLinesRoundTrip) {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 2000; ++i) {
    TetCoords c;
    for (double& x : c) {
      x = std::bit_cast<double>(rng());
      if (!std::isfinite(x)) x = -0.0;
    }
    c[3] = std::numeric_limits<double>::denorm_min();
    TetCoords back{};
    std::string error;
    ASSERT_TRUE(parse_line<kTetCoords>(format_line(c), back, error)) << error;
    for (std::size_t k = 0; k < c.size(); ++k)
      ASSERT_EQ(std::bit_cast<std::uint64_t>(back[k]), std::bit_cast<std::uint64_t>(c[k]));
  }
  TriCoords t{};
  std::string error;
  EXPECT_FALSE(parse_line<kTriCoords>("  # comment", t, error));
  EXPECT_TRUE(error.empty());
  EXPECT_FALSE(parse_line<kTriCoords>("", t, error));
  EXPECT_FALSE(parse_line<kTriCoords>("1 2 3", t, error));
  EXPECT_EQ(error, "expected 12 numbers, got 3");
  EXPECT_FALSE(parse_line<kTriCoords>("0 0 1 0 0 1 0 0 1 0 0 nan", t, error));
  EXPECT_FALSE(parse_line<kTriCoords>("0 0 1 0 0 1 0 0 1 0 0 1e999", t, error));
  EXPECT_FALSE(parse_line<kTriCoords>("0 0 1 0 0 1 0 0 1 0 0 1x", t, error));
  EXPECT_TRUE(parse_line<kTriCoords>("0 0 1 0 0 1 0 0 1 0 0 +1e-400", t, error)) << error;
  EXPECT_EQ(t[11], 0.0);
}

TEST(FuzzHarness, RoundToDoubleIsNearestEven) {
  using detail::round_to_double;
  constexpr double tiny = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(round_to_double(mpq_class(1, 3)), 1.0 / 3.0);
  EXPECT_EQ(round_to_double(mpq_class(-2, 3)), -2.0 / 3.0);
  EXPECT_EQ(round_to_double(mpq_class(0)), 0.0);
  // 1 + 2^-53 is a tie between 1 and 1 + 2^-52: to even, 1; a hair above rounds up.
  const mpz_class two53 = mpz_class(1) << 53;
  EXPECT_EQ(round_to_double(mpq_class(two53 + 1, two53)), 1.0);
  EXPECT_EQ(round_to_double(mpq_class(4 * two53 + 5, 4 * two53)), std::nextafter(1.0, 2.0));
  // Subnormals: 1.5 * 2^-1074 ties to 2 * 2^-1074; 0.4 * 2^-1074 rounds to 0.
  mpq_class q(3, 2);
  mpq_div_2exp(q.get_mpq_t(), q.get_mpq_t(), 1074);
  EXPECT_EQ(round_to_double(q), 2 * tiny);
  mpq_class r(2, 5);
  mpq_div_2exp(r.get_mpq_t(), r.get_mpq_t(), 1074);
  EXPECT_EQ(round_to_double(r), 0.0);
  // Overflow: DBL_MAX is exact, 2^1024 is not a double.
  EXPECT_EQ(round_to_double(mpq_class(std::numeric_limits<double>::max())),
            std::numeric_limits<double>::max());
  EXPECT_TRUE(std::isinf(round_to_double(mpq_class(mpz_class(1) << 1024))));
  std::mt19937_64 rng(3);
  for (int i = 0; i < 1000; ++i) {
    const double x = std::bit_cast<double>(rng() >> 1);
    if (std::isfinite(x)) {
      ASSERT_EQ(round_to_double(mpq_class(x)), x);
    }
  }
}

TEST(FuzzHarness, ContractHoldsOnSimplePairsAndFlagsViolations) {
  const tetia::Tet ref{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  const tetia::Tet shifted{{{.25, .25, .25}, {1.25, .25, .25}, {.25, 1.25, .25}, {.25, .25, 1.25}}};
  EXPECT_EQ(check_tet_contract(ref, ref), "");
  EXPECT_EQ(check_tet_contract(ref, shifted), "");
  const tetia::Triangle a{{{0, 0}, {1, 0}, {0, 1}}}, b{{{.25, .25}, {1.25, .25}, {.25, 1.25}}};
  EXPECT_EQ(check_tri_contract(a, b), "");
  // The checks themselves: a non-finite input is reported, not passed to the exact reference.
  tetia::Tet bad = ref;
  bad[2].y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(message_kind(check_tet_contract(bad, ref)), "input-nonfinite");
  detail::Observed<tetia::Vec2> o;
  o.v = 1.0;  // more than the smaller triangle's 1/2
  o.entries = {{"other", 0.5}};
  o.first_moments = {{"first", {std::nan(""), 0.0}}};
  const auto exact = [&] { return tetia::exact::intersection_area(a, b); };
  const std::string m = detail::judge(a, b, "area", o, exact);
  const std::vector<std::string> kinds = message_kinds(m);
  ASSERT_GE(kinds.size(), 3u) << m;
  EXPECT_EQ(kinds[0], "area-exceeds-min") << m;
  EXPECT_EQ(kinds[1], "mismatch[other]") << m;
  EXPECT_EQ(kinds[2], "moments-nonfinite") << m;
  o = {};  // v = 0 for an overlap of 1/8
  EXPECT_EQ(message_kind(detail::judge(a, b, "area", o, exact)), "vanished");
}

}  // namespace
