// app/parse.hpp -- strict parsing of whitespace-separated numbers on one input line.
//
// Contract: a field is a maximal run of non-blank characters (blanks: space, tab, CR, VT, FF).
// Every field must be a complete decimal floating-point number in the syntax of std::from_chars
// (an optional leading '+' is also accepted) and finite: "1.0abc", "0x10", "nan", "inf" and
// overflow ("1e999") are errors. A number too small for a double (1e-400) rounds to zero or a
// subnormal, as strtod does. The line must hold exactly the expected number of fields.
// Locale independent.
#pragma once

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <span>
#include <string>
#include <string_view>
#include <system_error>

namespace tetia::app {

inline constexpr bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// True for a line that holds no data: only blanks, or a '#' comment after optional blanks.
inline bool is_blank_or_comment(std::string_view line) {
  std::size_t i = 0;
  while (i < line.size() && is_blank(line[i])) ++i;
  return i == line.size() || line[i] == '#';
}

namespace detail {

/// A field as it is quoted in a diagnostic: control characters replaced, long fields cut.
inline std::string quote_field(std::string_view field) {
  constexpr std::size_t max_shown = 40;
  std::string q = "'";
  for (std::size_t i = 0; i < field.size() && i < max_shown; ++i) {
    const auto c = static_cast<unsigned char>(field[i]);
    q += (c < 0x20 || c == 0x7f) ? '?' : static_cast<char>(c);
  }
  if (field.size() > max_shown) q += "...";
  q += "'";
  return q;
}

/// Parses one complete field; returns an empty string or what is wrong with it.
inline std::string parse_field(std::string_view field, double& value) {
  std::string_view digits = field;
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') digits.remove_prefix(1);
  const char* first = digits.data();
  const char* last = first + digits.size();
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
  if (ptr != last || ec == std::errc::invalid_argument) {
    return quote_field(field) + " is not a number";
  }
  if (ec == std::errc::result_out_of_range) {
    // from_chars reports overflow and underflow alike; strtod tells them apart.
    const std::string copy(digits);
    v = std::strtod(copy.c_str(), nullptr);
    if (std::isinf(v)) return quote_field(field) + " is out of range";
  } else if (!std::isfinite(v)) {
    return quote_field(field) + " is not finite";
  }
  value = v;
  return {};
}

}  // namespace detail

/// Parses exactly out.size() numbers from line into out. Returns an empty string on success,
/// otherwise a one-line description of what is wrong (e.g. "field 3: '1.0abc' is not a number",
/// "expected 24 numbers, got 23").
inline std::string parse_numbers(std::string_view line, std::span<double> out) {
  std::size_t count = 0;
  std::size_t i = 0;
  const std::size_t n = line.size();
  for (;;) {
    while (i < n && is_blank(line[i])) ++i;
    if (i == n) break;
    const std::size_t begin = i;
    while (i < n && !is_blank(line[i])) ++i;
    double v = 0.0;
    std::string what = detail::parse_field(line.substr(begin, i - begin), v);
    if (!what.empty()) return "field " + std::to_string(count + 1) + ": " + what;
    if (count < out.size()) out[count] = v;
    ++count;
  }
  if (count != out.size()) {
    return "expected " + std::to_string(out.size()) + " numbers, got " + std::to_string(count);
  }
  return {};
}

}  // namespace tetia::app
