// app/pairs.cpp -- `tetia pairs`, see pairs.hpp.
#include "pairs.hpp"

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <exception>
#include <span>
#include <string>
#include <string_view>

#include "line_reader.hpp"
#include "parse.hpp"
#include "tetia/baselines.hpp"
#include "tetia/exact.hpp"
#include "tetia/tet_intersection.hpp"
#include "tetia/tri_intersection.hpp"

namespace tetia::app {

std::string_view algorithm_name(Algorithm a) {
  switch (a) {
    case Algorithm::tetia: return "tetia";
    case Algorithm::clip: return "clip";
    case Algorithm::pang: return "pang";
    case Algorithm::exact: return "exact";
  }
  return "?";
}

std::optional<Algorithm> parse_algorithm(std::string_view name) {
  for (Algorithm a : {Algorithm::tetia, Algorithm::clip, Algorithm::pang, Algorithm::exact}) {
    if (name == algorithm_name(a)) return a;
  }
  return std::nullopt;
}

std::string_view format_name(Format f) {
  switch (f) {
    case Format::volume: return "volume";
    case Format::json: return "json";
  }
  return "?";
}

std::optional<Format> parse_format(std::string_view name) {
  for (Format f : {Format::volume, Format::json}) {
    if (name == format_name(f)) return f;
  }
  return std::nullopt;
}

namespace {

/// Output buffered by hand: one fwrite per 64 KiB instead of one printf per number.
class Writer {
 public:
  explicit Writer(std::FILE* out) : out_(out) {}

  void put(std::string_view s) {
    if (s.size() > buf_.size() - len_) flush_buffer();
    if (s.size() > buf_.size()) {
      write(s.data(), s.size());
      return;
    }
    std::memcpy(buf_.data() + len_, s.data(), s.size());
    len_ += s.size();
  }
  void put(char c) {
    if (len_ == buf_.size()) flush_buffer();
    buf_[len_++] = c;
  }
  /// As printf("%.17g"): round-trips every double. Non-finite values as JSON's null if asked.
  void put_double(double v, bool json) {
    if (json && !std::isfinite(v)) {
      put("null");
      return;
    }
    if (buf_.size() - len_ < 32) flush_buffer();
    char* first = buf_.data() + len_;
    const auto r = std::to_chars(first, buf_.data() + buf_.size(), v,
                                 std::chars_format::general, 17);
    len_ += static_cast<std::size_t>(r.ptr - first);
  }
  void put_int(long long v) {
    if (buf_.size() - len_ < 24) flush_buffer();
    char* first = buf_.data() + len_;
    const auto r = std::to_chars(first, buf_.data() + buf_.size(), v);
    len_ += static_cast<std::size_t>(r.ptr - first);
  }

  /// Hands everything to the stream and flushes it. False once any write failed.
  bool flush() {
    flush_buffer();
    if (ok_ && std::fflush(out_) != 0) fail();
    return ok_;
  }
  bool ok() const { return ok_; }
  /// errno of the first failed write.
  int error_code() const { return errno_; }

 private:
  void flush_buffer() {
    if (len_ > 0) write(buf_.data(), len_);
    len_ = 0;
  }
  void write(const char* p, std::size_t n) {
    if (ok_ && std::fwrite(p, 1, n, out_) != n) fail();
  }
  void fail() {
    ok_ = false;
    errno_ = errno;
  }

  std::FILE* out_;
  std::array<char, 1 << 16> buf_{};
  std::size_t len_ = 0;
  bool ok_ = true;
  int errno_ = 0;
};

Tet tet_from(const double* c) {
  Tet t;
  for (int i = 0; i < 4; ++i) t[static_cast<std::size_t>(i)] = {c[3 * i], c[3 * i + 1], c[3 * i + 2]};
  return t;
}

void put_bits(Writer& w, unsigned bits) {
  w.put('[');
  bool first = true;
  for (int k = 0; k < 4; ++k) {
    if ((bits >> k) & 1u) {
      if (!first) w.put(", ");
      w.put_int(k);
      first = false;
    }
  }
  w.put(']');
}

void put_polyhedron_json(Writer& w, long long line, const Polyhedron& p) {
  w.put("{\"line\": ");
  w.put_int(line);
  w.put(", \"volume\": ");
  w.put_double(p.volume(), true);
  w.put(", \"corners\": [");
  for (int i = 0; i < p.num_corners(); ++i) {
    const Corner& c = p.corner(i);
    if (i > 0) w.put(", ");
    w.put("{\"point\": [");
    for (int d = 0; d < 3; ++d) {
      if (d > 0) w.put(", ");
      w.put_double(c.point[d], true);
    }
    w.put("], \"bary\": [");
    for (std::size_t d = 0; d < 4; ++d) {
      if (d > 0) w.put(", ");
      w.put_double(c.bary[d], true);
    }
    w.put("], \"labels\": [");
    for (std::size_t d = 0; d < 3; ++d) {
      if (d > 0) w.put(", ");
      w.put_int(c.labels[d]);
    }
    w.put("]}");
  }
  w.put("], \"facets\": [");
  for (int f = 0; f < p.num_facets(); ++f) {
    if (f > 0) w.put(", ");
    w.put("{\"label\": ");
    w.put_int(p.facet_label(f));
    w.put(", \"corners\": [");
    bool first = true;
    for (const std::uint8_t idx : p.facet(f)) {
      if (!first) w.put(", ");
      w.put_int(idx);
      first = false;
    }
    w.put("]}");
  }
  w.put("], \"touched_faces_of_v\": ");
  put_bits(w, p.touched_faces_of_v());
  w.put("}\n");
}

Triangle triangle_from(const double* c) {
  return {Vec2{c[0], c[1]}, Vec2{c[2], c[3]}, Vec2{c[4], c[5]}};
}

void put_polygon_json(Writer& w, long long line, const Polygon& p) {
  w.put("{\"line\": ");
  w.put_int(line);
  w.put(", \"area\": ");
  w.put_double(p.area(), true);
  w.put(", \"corners\": [");
  for (int i = 0; i < p.num_corners(); ++i) {
    const PolygonCorner& c = p.corner(i);
    if (i > 0) w.put(", ");
    w.put("{\"point\": [");
    w.put_double(c.point.x, true);
    w.put(", ");
    w.put_double(c.point.y, true);
    w.put("], \"bary\": [");
    for (std::size_t d = 0; d < 3; ++d) {
      if (d > 0) w.put(", ");
      w.put_double(c.bary[d], true);
    }
    w.put("], \"labels\": [");
    w.put_int(c.labels[0]);
    w.put(", ");
    w.put_int(c.labels[1]);
    w.put("]}");
  }
  w.put("], \"touched_edges_of_b\": ");
  put_bits(w, p.touched_edges_of_b());
  w.put("}\n");
}

double area_by(Algorithm a, const Triangle& A, const Triangle& B) {
  switch (a) {
    case Algorithm::tetia: return intersection_area(A, B);
    case Algorithm::clip: return baselines::clip_area(A, B);
    case Algorithm::pang: return baselines::pang_area(A, B);
    case Algorithm::exact: return exact::intersection_area_double(A, B);
  }
  return 0.0;
}

double volume_by(Algorithm a, const Tet& U, const Tet& V) {
  switch (a) {
    case Algorithm::tetia: return intersection_volume(U, V);
    case Algorithm::clip: return baselines::clip_volume(U, V);
    case Algorithm::pang: return baselines::pang_volume(U, V);
    case Algorithm::exact: return exact::intersection_volume_double(U, V);
  }
  return 0.0;
}

/// Flushes what was printed so far, then reports on `err`. Returns `code`.
int fail(Writer& w, std::FILE* err, int code, const std::string& message) {
  w.flush();
  std::fprintf(err, "tetia: %s\n", message.c_str());
  std::fflush(err);
  return code;
}

}  // namespace

int run_pairs(const PairsOptions& options, std::FILE* in, std::FILE* out, std::FILE* err) {
  Writer w(out);
  LineReader reader(in);
  // Flush before a read that may block: interactive or piped input sees its answers promptly,
  // and a large input costs one flush per read buffer.
  reader.set_before_read([&w] { w.flush(); });

  std::array<double, 24> c{};
  const bool planar = options.dimension == 2;
  const std::span<double> numbers(c.data(), planar ? 12 : 24);
  std::string_view line;
  while (reader.next(line)) {
    if (is_blank_or_comment(line)) continue;
    const long long n = reader.line_number();
    if (std::string what = parse_numbers(line, numbers); !what.empty()) {
      return fail(w, err, exit_bad_input, "line " + std::to_string(n) + ": " + what);
    }
    try {
      if (options.format == Format::json && options.algorithm == Algorithm::tetia) {
        if (planar) put_polygon_json(w, n, intersect(triangle_from(c.data()), triangle_from(c.data() + 6)));
        else put_polyhedron_json(w, n, intersect(tet_from(c.data()), tet_from(c.data() + 12)));
      } else {
        const double v = planar ? area_by(options.algorithm, triangle_from(c.data()), triangle_from(c.data() + 6))
                                : volume_by(options.algorithm, tet_from(c.data()), tet_from(c.data() + 12));
        if (options.format == Format::json) {
          w.put("{\"line\": ");
          w.put_int(n);
          w.put(planar ? ", \"area\": " : ", \"volume\": ");
          w.put_double(v, true);
          w.put("}\n");
        } else {
          w.put_double(v, false);
          w.put('\n');
        }
      }
    } catch (const std::exception& e) {
      return fail(w, err, exit_failure,
                  "line " + std::to_string(n) + ": " + std::string(algorithm_name(options.algorithm)) +
                      " failed: " + e.what());
    }
    if (!w.ok()) break;
  }
  if (reader.failed()) {
    return fail(w, err, exit_failure,
                std::string("error reading input: ") + std::strerror(reader.error_code()));
  }
  if (!w.flush()) {
    std::fprintf(err, "tetia: error writing output: %s\n", std::strerror(w.error_code()));
    std::fflush(err);
    return exit_failure;
  }
  return exit_ok;
}

}  // namespace tetia::app
