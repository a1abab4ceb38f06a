// fuzz/fuzz_operator_mtx.cpp -- libFuzzer target for the reader of saved remap operators in
// Matrix Market form (app/operator_mtx.cpp, what `tetia apply` reads): for any bytes, parsing
// either gives an operator whose sizes are within the meshes' bound given (4096 here) and whose
// weights are all finite, in a matrix of that size, or throws std::invalid_argument with a
// message "tetia: fuzz.mtx..."; anything else is a finding (another exception, a crash, a
// sanitizer report, a timeout, or an allocation beyond libFuzzer's -malloc_limit_mb).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>

#include "../app/operator_file.hpp"

namespace {

constexpr std::size_t kMostValues = 4096;

[[noreturn]] void finding(const char* what) {
  std::fprintf(stderr, "==== %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const tetia::app::OperatorFile op = tetia::app::parse_mtx(text, "fuzz.mtx", kMostValues);
    const auto& w = op.weights;
    if (static_cast<std::size_t>(w.rows()) > kMostValues || static_cast<std::size_t>(w.cols()) > kMostValues)
      finding("an operator larger than the bound given");
    for (Eigen::Index k = 0; k < w.nonZeros(); ++k)
      if (!std::isfinite(w.valuePtr()[k])) finding("a weight that is not finite");
    if (op.dimension != 2 && op.dimension != 3) finding("a dimension other than 2 or 3");
  } catch (const std::invalid_argument& e) {
    if (std::string_view(e.what()).rfind("tetia: fuzz.mtx", 0) != 0) {
      std::fprintf(stderr, "==== error message without the file name: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
