// fuzz/fuzz_msh_reader.cpp -- libFuzzer target for the strict .msh reader (src/io/msh_reader.hpp)
// and the assembly of its result into a mesh and fields (src/io/msh_mesh.hpp, finalize): for
// any bytes, reading either gives a finalized mesh or throws std::runtime_error with a message
// "tetia: fuzz.msh: ..."; anything else is a finding (another exception, a crash, a sanitizer
// report, a timeout, or an allocation beyond libFuzzer's -malloc_limit_mb, which
// scripts/fuzz.sh sets far below what the input's size would need to justify).
//
// The reader's sources are compiled into this target directly (fuzz/CMakeLists.txt): the
// `tetia` library would bring Gmsh, which the reader does not use.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>

#include "../src/io/mesh_assembly.hpp"
#include "../src/io/msh_mesh.hpp"
#include "../src/io/msh_reader.hpp"
#include "tetia/mesh.hpp"

namespace {

const std::string kName = "fuzz.msh";

// What read_any_mesh and read_msh_field do with the parsed file (src/io.cpp), minus the file.
template <class Mesh>
void assemble(const tetia::detail::MshFile& f) {
  tetia::detail::Extracted<Mesh> ex = tetia::detail::extract_msh<Mesh>(f, kName);
  if (ex.mesh.cells.empty()) return;
  const std::vector<tetia::detail::ViewData> views = tetia::detail::msh_views(f, true);
  tetia::finalize(ex.mesh, kName);
  for (const auto& v : views) {
    if (v.components != 1) continue;
    try {
      tetia::detail::field_values(kName, ex, views, v.name, v.type == "ElementData");
    } catch (const std::runtime_error& e) {
      if (std::string_view(e.what()).rfind("tetia: " + kName + ": ", 0) != 0) throw;
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const tetia::detail::MshFile f = tetia::detail::parse_msh(bytes, kName);
    const int dim = tetia::detail::msh_dimension(f);
    if (dim == 3) assemble<tetia::TetMesh>(f);
    if (dim == 2) assemble<tetia::TriMesh>(f);
  } catch (const std::runtime_error& e) {
    const std::string_view what = e.what();
    if (what.rfind("tetia: " + kName + ": ", 0) != 0) {
      std::fprintf(stderr, "==== error message without the file name: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
