// tests/test_cli.cpp -- the `tetia` executable end to end: options, the pairs input format,
// error reporting, output formats. Runs the binary named by TETIA_CLI_PATH through the shell.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "support/cli.hpp"

namespace {

namespace fs = std::filesystem;

using tetia::testcli::read_file;
using tetia::testcli::Result;
using tetia::testcli::shell_quote;

std::vector<std::string> lines_of(const std::string& s) {
  std::vector<std::string> v;
  std::istringstream in(s);
  for (std::string line; std::getline(in, line);) v.push_back(line);
  return v;
}

double to_double(const std::string& s) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  EXPECT_TRUE(end != s.c_str() && *end == '\0') << "not a number: '" << s << "'";
  return v;
}

/// A minimal JSON syntax check (RFC 8259 grammar, no semantic checks).
class JsonChecker {
 public:
  explicit JsonChecker(std::string_view s) : s_(s) {}
  bool valid() {
    ws();
    if (!value()) return false;
    ws();
    return i_ == s_.size();
  }

 private:
  void ws() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
  }
  bool lit(std::string_view t) {
    if (s_.substr(i_, t.size()) != t) return false;
    i_ += t.size();
    return true;
  }
  bool digits() {
    const std::size_t b = i_;
    while (i_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_]))) ++i_;
    return i_ > b;
  }
  bool number() {
    if (i_ < s_.size() && s_[i_] == '-') ++i_;
    if (i_ < s_.size() && s_[i_] == '0') {
      ++i_;
    } else if (!digits()) {
      return false;
    }
    if (i_ < s_.size() && s_[i_] == '.') {
      ++i_;
      if (!digits()) return false;
    }
    if (i_ < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E')) {
      ++i_;
      if (i_ < s_.size() && (s_[i_] == '+' || s_[i_] == '-')) ++i_;
      if (!digits()) return false;
    }
    return true;
  }
  bool string() {
    if (!lit("\"")) return false;
    while (i_ < s_.size() && s_[i_] != '"') {
      if (static_cast<unsigned char>(s_[i_]) < 0x20) return false;
      if (s_[i_] == '\\') ++i_;
      ++i_;
    }
    return lit("\"");
  }
  bool value() {
    if (i_ >= s_.size()) return false;
    const char c = s_[i_];
    if (c == '{') return container('}', true);
    if (c == '[') return container(']', false);
    if (c == '"') return string();
    if (c == 't') return lit("true");
    if (c == 'f') return lit("false");
    if (c == 'n') return lit("null");
    return number();
  }
  bool container(char close, bool object) {
    ++i_;
    ws();
    if (i_ < s_.size() && s_[i_] == close) {
      ++i_;
      return true;
    }
    for (;;) {
      ws();
      if (object) {
        if (!string()) return false;
        ws();
        if (!lit(":")) return false;
        ws();
      }
      if (!value()) return false;
      ws();
      if (i_ < s_.size() && s_[i_] == ',') {
        ++i_;
        continue;
      }
      return lit(std::string_view(&close, 1));
    }
  }

  std::string_view s_;
  std::size_t i_ = 0;
};

// The reference tetrahedron and some pairs, one per line.
constexpr const char* kRef = "0 0 0  1 0 0  0 1 0  0 0 1";
const std::string kIdentical = std::string(kRef) + "   " + kRef;
// V = U + (0.1, 0.1, 0.1): the intersection is {x, y, z >= 0.1, x + y + z <= 1}, edge 0.7.
const std::string kShifted = std::string(kRef) + "   0.1 0.1 0.1  1.1 0.1 0.1  0.1 1.1 0.1  0.1 0.1 1.1";
constexpr double kShiftedVolume = 0.343 / 6.0;
const std::string kDisjoint = std::string(kRef) + "   2 0 0  3 0 0  2 1 0  2 0 1";

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string templ = (fs::temp_directory_path() / "tetia_cli_test_XXXXXX").string();
    ASSERT_NE(::mkdtemp(templ.data()), nullptr);
    dir_ = templ;
    ASSERT_TRUE(fs::exists(TETIA_CLI_PATH)) << "CLI not built: " << TETIA_CLI_PATH;
  }
  void TearDown() override {
    std::error_code ec;
    if (!dir_.empty()) fs::remove_all(dir_, ec);
  }

  /// Runs `tetia <args>` with `input` on stdin.
  Result run(const std::string& args, const std::string& input = "") {
    const fs::path in = dir_ / ("in" + std::to_string(n_++));
    {
      std::ofstream f(in, std::ios::binary);
      f << input;
    }
    return tetia::testcli::run(TETIA_CLI_PATH, args, dir_, in);
  }

  /// Runs `tetia pairs <args>` on `input`, expects success, returns the output lines.
  std::vector<std::string> pairs_ok(const std::string& args, const std::string& input) {
    const Result r = run("pairs " + args, input);
    EXPECT_EQ(r.status, 0) << "stderr: " << r.err;
    EXPECT_EQ(r.err, "");
    return lines_of(r.out);
  }

  /// Runs `tetia pairs` on `input`, expects the error report for `line` and exit status 2, and
  /// that the first `printed` lines of output came out before it.
  void expect_bad_line(const std::string& input, int line, std::size_t printed,
                       const std::string& args = "") {
    SCOPED_TRACE("input: " + input);
    const Result r = run("pairs " + args, input);
    EXPECT_EQ(r.status, 2);
    const std::string prefix = "tetia: line " + std::to_string(line) + ": ";
    EXPECT_EQ(r.err.rfind(prefix, 0), 0u) << "stderr: " << r.err;
    EXPECT_GT(r.err.size(), prefix.size() + 1) << "the message says what is wrong";
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
    EXPECT_EQ(lines_of(r.out).size(), printed) << "stdout: " << r.out;
  }

  fs::path dir_;
  int n_ = 0;
};

TEST_F(CliTest, VersionPrintsNameAndVersion) {
  const Result r = run("--version");
  EXPECT_EQ(r.status, 0);
  ASSERT_EQ(r.out.rfind("tetia ", 0), 0u) << r.out;
  const std::string v = r.out.substr(6);
  ASSERT_FALSE(v.empty());
  EXPECT_TRUE(std::isdigit(static_cast<unsigned char>(v[0]))) << r.out;
  EXPECT_EQ(std::count(v.begin(), v.end(), '.'), 2) << r.out;
  EXPECT_EQ(v.back(), '\n');
}

TEST_F(CliTest, HelpExitsZero) {
  const Result r = run("--help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("pairs"), std::string::npos) << r.out;

  const Result s = run("pairs --help");
  EXPECT_EQ(s.status, 0);
  EXPECT_NE(s.out.find("--algorithm"), std::string::npos) << s.out;
  EXPECT_NE(s.out.find("--format"), std::string::npos) << s.out;
}

TEST_F(CliTest, NoSubcommandIsAUsageError) {
  const Result r = run("");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("pairs"), std::string::npos) << "help on stderr: " << r.err;
}

TEST_F(CliTest, UnknownOptionOrValueIsAUsageError) {
  EXPECT_EQ(run("pairs --algorithm nonsense", kIdentical + "\n").status, 2);
  EXPECT_EQ(run("pairs --format xml", kIdentical + "\n").status, 2);
  EXPECT_EQ(run("pairs --no-such-option", kIdentical + "\n").status, 2);
  EXPECT_EQ(run("nosuchcommand").status, 2);
}

TEST_F(CliTest, IdenticalReferenceTetsGiveOneSixth) {
  const auto out = pairs_ok("", kIdentical + "\n");
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(to_double(out[0]), 1.0 / 6.0, 1e-15);
}

TEST_F(CliTest, VolumesArePrintedWith17SignificantDigits) {
  const auto out = pairs_ok("--algorithm exact", kIdentical + "\n");
  ASSERT_EQ(out.size(), 1u);
  char expected[64];
  std::snprintf(expected, sizeof expected, "%.17g", 1.0 / 6.0);
  EXPECT_EQ(out[0], expected);
}

TEST_F(CliTest, CommentsAndBlankLinesAreSkipped) {
  const std::string input = "# a comment\n"
                            "\n" +
                            kIdentical + "\n" +
                            "   # an indented comment\n"
                            "   \t  \n"
                            "\t" + kDisjoint + "  \n" +
                            "#" + kIdentical + "\n" +  // a commented-out pair
                            kShifted;                 // no final newline
  const auto out = pairs_ok("", input);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_NEAR(to_double(out[0]), 1.0 / 6.0, 1e-15);
  EXPECT_EQ(to_double(out[1]), 0.0);
  EXPECT_NEAR(to_double(out[2]), kShiftedVolume, 1e-15);
}

TEST_F(CliTest, TabsAndCrlfAreAccepted) {
  std::string tabbed = kIdentical;
  for (char& c : tabbed) {
    if (c == ' ') c = '\t';
  }
  const auto out = pairs_ok("", tabbed + "\r\n" + kDisjoint + "\r\n");
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(to_double(out[0]), 1.0 / 6.0, 1e-15);
}

TEST_F(CliTest, EmptyInputPrintsNothing) {
  EXPECT_TRUE(pairs_ok("", "").empty());
  EXPECT_TRUE(pairs_ok("", "# only a comment\n\n").empty());
}

TEST_F(CliTest, BadLineStopsTheRunAfterEarlierLines) {
  const std::string good = kIdentical + "\n" + kDisjoint + "\n";
  expect_bad_line(good + "0 0 0 1 0 0 0 1 0 0 0 1 0 0 0 1 0 0 0 1 0 0 0 1.0abc\n" + kIdentical + "\n", 3, 2);
  // Line numbers count physical lines, comments and blank lines included.
  expect_bad_line("# header\n\n" + kIdentical + "\nnot numbers at all\n", 4, 1);
  // The same in json format: the earlier object is out before the error.
  expect_bad_line(good + "1 2 3\n", 3, 2, "--format json");
}

TEST_F(CliTest, WrongCountsAreRejected) {
  const std::string good = kIdentical + "\n" + kShifted + "\n";
  expect_bad_line(good + kIdentical + " 1\n", 3, 2);                  // 25 numbers
  expect_bad_line(good + "0 0 0 1 0 0 0 1 0 0 0 1 0 0 0 1 0 0 0 1 0 0 0\n", 3, 2);  // 23
  const Result r = run("pairs", good + kIdentical + " 7\n");
  EXPECT_NE(r.err.find("24"), std::string::npos) << r.err;
}

TEST_F(CliTest, NonFiniteAndOverflowAreRejected) {
  const std::string good = kIdentical + "\n" + kDisjoint + "\n";
  const std::string head = "0 0 0 1 0 0 0 1 0 0 0 1 0 0 0 1 0 0 0 1 0 0 0 ";
  for (const char* bad : {"nan", "NaN", "-nan", "inf", "-inf", "+inf", "infinity", "1e999", "-1e999",
                          "1.0abc", "0x10", "1e", "--1", "1,0", "abc"}) {
    SCOPED_TRACE(bad);
    expect_bad_line(good + head + bad + "\n", 3, 2);
  }
  // A bad field in the middle is reported too.
  expect_bad_line(good + "0 0 0 1 0 0 nan 1 0 0 0 1 0 0 0 1 0 0 0 1 0 0 0 1\n", 3, 2);
}

TEST_F(CliTest, AcceptedNumberSyntax) {
  // Signs, exponents, leading and trailing dots, an underflow to zero.
  const std::string v = "+0 -0.0 0e5 1. 0 0 0 1 0 .0 0 1e0   0 0 0 1e-400 1 0 1 0 0 0 0 1.000";
  const auto out = pairs_ok("", v + "\n");
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(to_double(out[0]), 1.0 / 6.0, 1e-15);
}

TEST_F(CliTest, JsonForTetiaHasTheShape) {
  const auto out = pairs_ok("--format json", "# c\n" + kIdentical + "\n" + kDisjoint + "\n");
  ASSERT_EQ(out.size(), 2u);
  for (const std::string& obj : out) {
    EXPECT_TRUE(JsonChecker(obj).valid()) << obj;
    for (const char* key : {"\"line\"", "\"volume\"", "\"corners\"", "\"facets\"", "\"touched_faces_of_v\""}) {
      EXPECT_NE(obj.find(key), std::string::npos) << key << " missing in " << obj;
    }
  }
  EXPECT_NE(out[0].find("\"line\": 2,"), std::string::npos) << out[0];
  EXPECT_NE(out[1].find("\"line\": 3,"), std::string::npos) << out[1];
  // The identical pair is the whole tetrahedron: corners with points, barycentrics and labels.
  for (const char* key : {"\"point\"", "\"bary\"", "\"labels\"", "\"label\""}) {
    EXPECT_NE(out[0].find(key), std::string::npos) << key << " missing in " << out[0];
  }
  // The disjoint pair is empty.
  EXPECT_NE(out[1].find("\"corners\": []"), std::string::npos) << out[1];
}

TEST_F(CliTest, JsonForReferencesHasLineAndVolume) {
  for (const char* algorithm : {"clip", "pang", "exact"}) {
    SCOPED_TRACE(algorithm);
    const auto out = pairs_ok(std::string("--format json --algorithm ") + algorithm, kShifted + "\n");
    ASSERT_EQ(out.size(), 1u);
    EXPECT_TRUE(JsonChecker(out[0]).valid()) << out[0];
    EXPECT_EQ(out[0].rfind("{\"line\": 1, \"volume\": ", 0), 0u) << out[0];
    EXPECT_EQ(out[0].find("corners"), std::string::npos) << out[0];
  }
}

TEST_F(CliTest, EveryAlgorithmRuns) {
  const std::string input = kShifted + "\n" + kDisjoint + "\n";
  for (const char* algorithm : {"tetia", "clip", "pang", "exact"}) {
    SCOPED_TRACE(algorithm);
    const auto out = pairs_ok(std::string("--algorithm ") + algorithm, input);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_NEAR(to_double(out[0]), kShiftedVolume, 1e-12);
    EXPECT_EQ(to_double(out[1]), 0.0);
  }
}

TEST_F(CliTest, InputFileArgument) {
  const fs::path p = dir_ / "pairs.txt";
  {
    std::ofstream f(p);
    f << kIdentical << "\n";
  }
  const Result r = run("pairs " + shell_quote(p.string()));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(lines_of(r.out).size(), 1u);
  const Result missing = run("pairs " + shell_quote((dir_ / "missing.txt").string()));
  EXPECT_EQ(missing.status, 2);
  EXPECT_EQ(missing.err.rfind("tetia: ", 0), 0u) << missing.err;
}

TEST_F(CliTest, LargeInputCrossesBufferBoundaries) {
  // More than one read buffer (1 MiB) of input, lines of varying length.
  constexpr int n = 30000;
  std::string input;
  for (int i = 0; i < n; ++i) {
    input += (i % 3 == 0) ? kIdentical : (i % 3 == 1 ? kShifted : kDisjoint);
    input += std::string(static_cast<std::size_t>(i % 7), ' ');
    input += '\n';
  }
  ASSERT_GT(input.size(), std::size_t{1} << 20);
  const auto out = pairs_ok("", input);
  ASSERT_EQ(out.size(), static_cast<std::size_t>(n));
  for (int i = 0; i < n; i += 997) {
    const double expected = (i % 3 == 0) ? 1.0 / 6.0 : (i % 3 == 1 ? kShiftedVolume : 0.0);
    EXPECT_NEAR(to_double(out[static_cast<std::size_t>(i)]), expected, 1e-15) << "pair " << i;
  }
  // And an error at the very end is reported with the right line number.
  expect_bad_line(input + "1 2 3\n", n + 1, static_cast<std::size_t>(n));
}

// --- Dimension 2: `tetia pairs --dim 2`, triangle pairs of 12 numbers ---------------------

// The unit right triangle with itself, with a copy moved by (0.5, 0): overlap 1/8, and with a
// triangle beyond its hypotenuse (touching at a vertex only: 0).
const std::string kTriIdentical = "0 0 1 0 0 1   0 0 1 0 0 1";
const std::string kTriShifted = "0 0 1 0 0 1   0.5 0 1.5 0 0.5 1";
const std::string kTriTouching = "0 0 1 0 0 1   1 0 2 0 1 1";

TEST_F(CliTest, Dim2AreasForEveryAlgorithm) {
  const std::string input = kTriIdentical + "\n# comment\n" + kTriShifted + "\n" + kTriTouching + "\n";
  for (const char* algorithm : {"tetia", "clip", "pang", "exact"}) {
    SCOPED_TRACE(algorithm);
    const auto out = pairs_ok(std::string("--dim 2 --algorithm ") + algorithm, input);
    ASSERT_EQ(out.size(), 3u);
    EXPECT_NEAR(to_double(out[0]), 0.5, 1e-15);
    EXPECT_NEAR(to_double(out[1]), 0.125, 1e-15);
    EXPECT_EQ(to_double(out[2]), 0.0);
  }
  // Dimension 3 stays the default, and reads 24 numbers.
  expect_bad_line(kTriIdentical + "\n", 1, 0);
}

TEST_F(CliTest, Dim2JsonHasAreaCornersAndTouchedEdges) {
  const auto out = pairs_ok("--dim 2 --format json", kTriShifted + "\n" + kTriTouching + "\n");
  ASSERT_EQ(out.size(), 2u);
  for (const std::string& obj : out) {
    EXPECT_TRUE(JsonChecker(obj).valid()) << obj;
    for (const char* key : {"\"line\"", "\"area\"", "\"corners\"", "\"touched_edges_of_b\""})
      EXPECT_NE(obj.find(key), std::string::npos) << key << " missing in " << obj;
    EXPECT_EQ(obj.find("\"volume\""), std::string::npos) << obj;
  }
  EXPECT_NE(out[0].find("\"labels\""), std::string::npos) << out[0];
  EXPECT_NE(out[1].find("\"corners\": []"), std::string::npos) << out[1];
  const auto ref = pairs_ok("--dim 2 --format json --algorithm exact", kTriShifted + "\n");
  ASSERT_EQ(ref.size(), 1u);
  EXPECT_EQ(ref[0], "{\"line\": 1, \"area\": 0.125}");
}

TEST_F(CliTest, Dim2BadLinesAndBadDimension) {
  expect_bad_line(kTriIdentical + "\n0 0 1 0 0 1 0 0 1 0 0\n", 2, 1, "--dim 2");
  expect_bad_line("0 0 1 0 0 1 0 0 1 0 0 nan\n", 1, 0, "--dim 2");
  expect_bad_line(kTriIdentical + " 5\n", 1, 0, "--dim 2");
  EXPECT_EQ(run("pairs --dim 4", kTriIdentical + "\n").status, 2);
  const Result h = run("pairs --help");
  EXPECT_NE(h.out.find("--dim"), std::string::npos) << h.out;
}

}  // namespace
