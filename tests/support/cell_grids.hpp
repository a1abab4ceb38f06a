// tests/support/cell_grids.hpp -- .msh files of hexahedra and prisms for the tests of split
// cells (test_cell_types.cpp, test_cli_mesh.cpp).
#pragma once

#include <array>
#include <sstream>
#include <string>

namespace tetia::testsupport {

// An n x n x n grid of unit cubes as a .msh 2.2 file: node (i, j, k) has tag 1 + i + (n+1) j +
// (n+1)^2 k, scrambled by `perm` (a multiplier mod a prime above the node count, so that the
// smallest tag of a cell is not always its first corner). Cubes are hexahedra; with `mixed`,
// the columns with i + j odd are two prisms each instead (split along the diagonal from (i, j)
// to (i + 1, j + 1), the same in the whole column, as an extruded mesh has it: the prisms'
// triangles meet triangles, their quadrilaterals meet the hexahedra's).
inline std::string grid_msh(int n, bool mixed, bool with_data) {
  const int m = n + 1;
  const auto node = [&](int i, int j, int k) { return 1 + i + m * j + m * m * k; };
  const auto tag = [&](int v) { return 1 + (static_cast<long long>(v) * 7919) % 100003; };  // distinct for v < 100003
  // (std::ostringstream: g++ 12's -Wrestrict misreads chains of string concatenations.)
  std::ostringstream s, el, data;
  s << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << m * m * m << "\n";
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) s << tag(node(i, j, k)) << ' ' << i << ' ' << j << ' ' << k << '\n';
  s << "$EndNodes\n$Elements\n";
  int ne = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int c[8] = {node(i, j, k),     node(i + 1, j, k),     node(i + 1, j + 1, k),     node(i, j + 1, k),
                          node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)};
        if (mixed && (i + j) % 2 == 1) {
          // Two prisms: bottom triangles (0, 1, 2) and (0, 2, 3), counter-clockwise from above.
          for (const auto& p : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
            el << ++ne << " 6 2 1 1";
            for (const int v : {p[0], p[1], p[2], p[0] + 4, p[1] + 4, p[2] + 4}) el << ' ' << tag(c[v]);
            el << '\n';
            data << ne << ' ' << ne * 10 << '\n';
          }
        } else {
          el << ++ne << " 5 2 1 1";
          for (int v = 0; v < 8; ++v) el << ' ' << tag(c[v]);
          el << '\n';
          data << ne << ' ' << ne * 10 << '\n';
        }
      }
  s << ne << '\n' << el.str() << "$EndElements\n";
  if (with_data) s << "$ElementData\n1\n\"ten\"\n1\n0.0\n3\n0\n1\n" << ne << '\n' << data.str() << "$EndElementData\n";
  return s.str();
}

}  // namespace tetia::testsupport
