// fuzz_replay -- checks kept inputs against the kernel contract (fuzz/kernel_contract.hpp)
// outside libFuzzer: crash artifacts, corpus files, and text files of pairs (fuzz/inputs.hpp).
//
//   fuzz_replay --dim 3|2 [--decode] FILE...
//
// Prints one verdict per case, "WHERE: ok" or "WHERE: FAIL MESSAGE". With --decode it prints
// each case as a text line under a '#' comment with its verdict instead, so that crash
// artifacts turn into a text file for fuzz/regressions/ (or for `tetia pairs`):
//   fuzz_replay --dim 3 --decode build-fuzz/artifacts/fuzz_tet_kernel-crash-* > case.txt
// Exit status: 0 every case holds, 1 some case violates the contract, 2 usage or input error.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "inputs.hpp"
#include "kernel_contract.hpp"

namespace {

int usage() {
  std::fprintf(stderr, "usage: fuzz_replay --dim 3|2 [--decode] FILE...\n");
  return 2;
}

template <std::size_t N>
int replay(const std::vector<std::string>& files, bool decode_mode) {
  using namespace tetia::fuzz;
  int status = 0;
  for (const auto& file : files)
    for (const Case<N>& c : read_cases<N>(file)) {
      if (!c.error.empty()) {
        std::fprintf(stderr, "fuzz_replay: %s: %s\n", c.where.c_str(), c.error.c_str());
        status = 2;
        continue;
      }
      const std::string message = check_contract(c.coords);
      const std::string verdict = message.empty() ? "ok" : "FAIL " + message;
      if (decode_mode)
        std::printf("# %s: %s\n%s\n", c.where.c_str(), verdict.c_str(),
                    format_line(c.coords).c_str());
      else
        std::printf("%s: %s\n", c.where.c_str(), verdict.c_str());
      if (!message.empty() && status == 0) status = 1;
    }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  int dim = 0;
  bool decode_mode = false;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--dim") == 0 && i + 1 < argc) {
      const std::string d = argv[++i];
      dim = d == "3" ? 3 : d == "2" ? 2 : -1;
    } else if (std::strcmp(argv[i], "--decode") == 0) {
      decode_mode = true;
    } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
      return usage();
    } else {
      files.emplace_back(argv[i]);
    }
  }
  if (dim <= 0 || files.empty()) return usage();
  return dim == 3 ? replay<tetia::fuzz::kTetCoords>(files, decode_mode)
                  : replay<tetia::fuzz::kTriCoords>(files, decode_mode);
}
