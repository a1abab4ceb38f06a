// app/mesh_commands.hpp -- `tetia supermesh`, `tetia remap` and `tetia demo`: the mesh side of
// the command line, for tetrahedral and triangular meshes (the dimension comes from the files;
// two files of different dimensions are a usage error). Each prints a JSON summary on stdout,
// progress on stderr when stderr is a terminal, and returns an exit code (0 ok, 1 failure, 2 bad
// usage or bad input file).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tetia/io.hpp"

namespace tetia::app {

struct SupermeshCommand {
  std::string source, target, output;  // output: VTU of the supermesh's tetrahedralization
  int threads = 0;
  std::string search = "front";
  bool ascii = false;  // the VTU as text instead of compressed binary
  bool progress = false, quiet = false;  // force the progress line on or off (app/progress.hpp)
  bool corner_nodes = false;             // read higher-order cells by their corners (straight)
  std::string partition = "morton";      // under mpiexec (app/mpi_mode.hpp)
};

struct RemapCommand {
  std::string source, target, output, matrix;
  std::vector<std::string> fields;  // --field, repeatable
  std::string expr;
  std::int64_t step = kOnlyStep;    // --step: the time step of the fields
  int order = 0;
  // The method (app/remap_method.hpp): --bounded, --lumped, --discontinuous, --reconstruct.
  bool bounded = false, lumped = false, discontinuous = false;
  std::string reconstruct = "none";  // none or linear
  std::string normalize = "full";    // full or covered
  std::string uncovered = "flag";    // flag, nan, zero or keep
  std::string save_operator;         // .mtx or .nc (app/operator_file.hpp)
  int threads = 0;
  bool ascii = false;  // the VTU as text instead of compressed binary
  bool progress = false, quiet = false;  // force the progress line on or off (app/progress.hpp)
  bool corner_nodes = false;             // read higher-order cells by their corners (straight)
  std::string partition = "morton";      // under mpiexec (app/mpi_mode.hpp)
};

// `tetia apply OPERATOR SOURCE TARGET`: a saved operator (app/operator_file.hpp) applied to
// fields of the source file, without the supermesh.
struct ApplyCommand {
  std::string op, source, target, output;
  std::vector<std::string> fields;
  std::int64_t step = kOnlyStep;
  std::string uncovered = "flag";
  int threads = 0;
  bool ascii = false, progress = false, quiet = false, corner_nodes = false;
};

struct DemoCommand {
  std::string output_dir = "tetia-demo";
  double size = 0.0;  // element size of the finer mesh; 0: 0.12 in 3D, 0.03 in 2D
  int threads = 0;
  int dim = 3;  // 3: box and ball; 2: rectangle, disk and annulus
};

int run_supermesh(const SupermeshCommand& cmd);
int run_remap(const RemapCommand& cmd);
int run_apply(const ApplyCommand& cmd);
int run_demo(const DemoCommand& cmd);

}  // namespace tetia::app
