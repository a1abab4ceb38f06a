// app/operator_mtx.cpp -- remap operators as Matrix Market files (app/operator_file.hpp): the
// writer, and a strict reader of the text (every line checked and named in errors; sizes
// checked against what the meshes justify before anything of that size is allocated).
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "operator_file.hpp"

namespace tetia::app {

void write_mtx(const std::string& file, const OperatorFile& op) {
  std::FILE* out = std::fopen(file.c_str(), "wb");
  if (out == nullptr) throw std::runtime_error("tetia: " + file + ": cannot write: " + std::strerror(errno));
  std::fprintf(out, "%%%%MatrixMarket matrix coordinate real general\n");
  std::fprintf(out, "%% tetia remap operator: (W u)_i is the remap of u at target value i (tetia apply)\n");
  std::fprintf(out, "%% tetia-operator dimension=%d method=%s normalize=%s rows=%s columns=%s\n", op.dimension,
               op.method.c_str(), op.normalize.c_str(), location_name(op.rows), location_name(op.columns));
  std::fprintf(out, "%lld %lld %lld\n", static_cast<long long>(op.weights.rows()),
               static_cast<long long>(op.weights.cols()), static_cast<long long>(op.weights.nonZeros()));
  for (Eigen::Index r = 0; r < op.weights.outerSize(); ++r)
    for (SparseMatrix::InnerIterator it(op.weights, r); it; ++it)
      std::fprintf(out, "%lld %lld %.17g\n", static_cast<long long>(r + 1), static_cast<long long>(it.col() + 1),
                   it.value());
  const bool failed = std::ferror(out) != 0;
  if (std::fclose(out) != 0 || failed) throw std::runtime_error("tetia: " + file + ": write failed");
}

namespace {

// A whole non-negative integer below 2^31 (indices and sizes), or a finite double.
bool parse_count(const std::string& word, long long& v) {
  if (word.empty() || word.size() > 10) return false;
  for (const char c : word)
    if (c < '0' || c > '9') return false;
  v = std::atoll(word.c_str());
  return v < (1LL << 31);
}
bool parse_value(const std::string& word, double& v) {
  char* end = nullptr;
  errno = 0;
  v = std::strtod(word.c_str(), &end);
  return !word.empty() && end == word.c_str() + word.size() && std::isfinite(v);
}

}  // namespace

OperatorFile parse_mtx(std::string_view text, const std::string& file, std::size_t max_values, bool description_only) {
  std::istringstream in{std::string(text)};
  OperatorFile op;
  std::string line;
  std::size_t number = 0;
  const auto where = [&] { return "tetia: " + file + ":" + std::to_string(number); };
  if (!std::getline(in, line) || (++number, line.rfind("%%MatrixMarket matrix coordinate real general", 0) != 0))
    throw std::invalid_argument("tetia: " + file + ":1: not a Matrix Market file of a real sparse matrix "
                                "('%%MatrixMarket matrix coordinate real general')");
  bool described = false;
  long long rows = -1, cols = -1, entries = -1;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.rfind("%", 0) == 0) {
      if (line.rfind("% tetia-operator ", 0) == 0) {
        std::istringstream words(line.substr(17));
        std::string w;
        std::string rows_word, cols_word;
        while (words >> w) {
          const auto eq = w.find('=');
          if (eq == std::string::npos) throw std::invalid_argument(where() + ": '" + w + "' is not key=value");
          const std::string key = w.substr(0, eq), value = w.substr(eq + 1);
          if (key == "dimension") op.dimension = value == "2" ? 2 : value == "3" ? 3 : 0;
          else if (key == "method") op.method = value;
          else if (key == "normalize") op.normalize = value;
          else if (key == "rows") rows_word = value;
          else if (key == "columns") cols_word = value;
        }
        op.rows = parse_location(rows_word, where());
        op.columns = parse_location(cols_word, where());
        check_description(op, where());
        described = true;
      }
      continue;
    }
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    std::istringstream words(line);
    std::string a, b, c, extra;
    words >> a >> b >> c;
    if (words >> extra) throw std::invalid_argument(where() + ": more than three numbers");
    if (rows < 0) {
      if (!parse_count(a, rows) || !parse_count(b, cols) || !parse_count(c, entries))
        throw std::invalid_argument(where() + ": the size line must be three counts: rows, columns, entries");
      break;
    }
  }
  if (!described)
    throw std::invalid_argument("tetia: " + file + ": no '% tetia-operator ...' line: not an operator that "
                                "'tetia remap --save-operator' wrote (it says what the rows and columns are)");
  if (rows < 0) throw std::invalid_argument("tetia: " + file + ": no size line");
  if (description_only) return op;
  // Nothing is allocated for more than the file or the meshes justify: an entry takes at least
  // six bytes ("1 1 0\n"), and the rows and columns are the meshes' values.
  if (static_cast<unsigned long long>(entries) > text.size() / 6)
    throw std::invalid_argument(where() + ": " + std::to_string(entries) + " entries are more than the file holds");
  if (static_cast<unsigned long long>(rows) > max_values || static_cast<unsigned long long>(cols) > max_values)
    throw std::invalid_argument(where() + ": a " + std::to_string(rows) + " x " + std::to_string(cols) +
                                " operator is larger than the meshes have values (" + std::to_string(max_values) + ")");
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(entries));
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '%') continue;
    std::istringstream words(line);
    std::string a, b, c, extra;
    words >> a >> b >> c;
    long long i = 0, j = 0;
    double v = 0.0;
    if (!parse_count(a, i) || !parse_count(b, j) || !parse_value(c, v) || (words >> extra))
      throw std::invalid_argument(where() + ": an entry must be: row column value (a finite number)");
    if (i < 1 || i > rows || j < 1 || j > cols)
      throw std::invalid_argument(where() + ": entry (" + a + ", " + b + ") outside the " + std::to_string(rows) +
                                  " x " + std::to_string(cols) + " matrix");
    if (static_cast<long long>(t.size()) == entries)
      throw std::invalid_argument(where() + ": more entries than the size line's " + std::to_string(entries));
    t.emplace_back(static_cast<int>(i - 1), static_cast<int>(j - 1), v);
  }
  if (static_cast<long long>(t.size()) != entries)
    throw std::invalid_argument("tetia: " + file + ": " + std::to_string(t.size()) + " entries, the size line says " +
                                std::to_string(entries));
  op.weights = from_entries(static_cast<std::size_t>(rows), static_cast<std::size_t>(cols), t, "tetia: " + file);
  return op;
}

OperatorFile read_mtx(const std::string& file, std::size_t max_values, bool description_only) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::invalid_argument("tetia: " + file + ": cannot open: " + std::strerror(errno));
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return parse_mtx(bytes.str(), file, max_values, description_only);
}

}  // namespace tetia::app
