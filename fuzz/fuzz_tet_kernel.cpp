// fuzz_tet_kernel -- libFuzzer target for the 3D kernel's contract (fuzz/kernel_contract.hpp)
// on the pairs of tetrahedra of fuzz/decode.hpp. See fuzz/README.md.
#include "fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return tetia::fuzz::fuzz_one_input<tetia::fuzz::kTetCoords>(data, size);
}
