#!/usr/bin/env python3
"""Build a mortar coupling matrix between two non-matching meshes of an interface and check it.

    /usr/bin/python3 examples/python/mortar_coupling.py [--refine N]

Two triangulations of the same interface (the unit square, as in a mortar method coupling two
subdomains through a plane) that do not match: a structured one and an unstructured one. tetia
gives the mixed mass matrix M_ts (rows: nodes of the mortar side t, columns: nodes of the
non-mortar side s; entry (i, j) = integral of phi_i^t phi_j^s over the interface) and the mass
matrix M_t. Checks, printed and asserted:
  - row sums of M_ts equal those of M_t (both integrate phi_i^t against 1: the basis functions
    of s sum to one), and the total is the interface's area;
  - column sums of M_ts equal the integrals of the phi_j^s (the lumped mass of s);
  - the mortar projection P = M_t^-1 M_ts reproduces constants and linear functions.
"""

import argparse

import numpy as np
import scipy.sparse.linalg
from scipy.spatial import Delaunay

import tetia


def structured_square(n):
    g = np.linspace(0.0, 1.0, n + 1)
    x, y = np.meshgrid(g, g, indexing="ij")
    points = np.stack([x.ravel(), y.ravel()], axis=1)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    quads = np.array([[idx[i, j], idx[i + 1, j], idx[i + 1, j + 1], idx[i, j + 1]]
                      for i in range(n) for j in range(n)])
    return tetia.Mesh(points, {"quad": quads}, name="structured")


def unstructured_square(n, seed=5):
    rng = np.random.default_rng(seed)
    boundary = np.linspace(0.0, 1.0, n + 1)[1:-1]
    edges = np.vstack([np.stack([boundary, 0 * boundary], 1), np.stack([boundary, 1 + 0 * boundary], 1),
                       np.stack([0 * boundary, boundary], 1), np.stack([1 + 0 * boundary, boundary], 1)])
    corners = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], dtype=float)
    points = np.vstack([corners, edges, 0.02 + 0.96 * rng.random((n * n, 2))])
    return tetia.Mesh(points, Delaunay(points).simplices, name="unstructured")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    parser.add_argument("--refine", type=int, default=12, help="cells per side of the structured mesh")
    n = parser.parse_args().refine
    mortar, nonmortar = structured_square(n), unstructured_square(n + 3)
    coupling = tetia.Remap(nonmortar, mortar, order=1)  # source s (non-mortar) -> target t (mortar)
    M_ts, M_t = coupling.mixed_mass, coupling.target_mass
    print(f"mortar side: {mortar.num_points} nodes ({mortar.num_cells} quadrilaterals), non-mortar side: "
          f"{nonmortar.num_points} nodes ({nonmortar.num_cells} triangles)")
    print(f"M_ts: {M_ts.shape[0]} x {M_ts.shape[1]}, {M_ts.nnz} nonzeros; M_t: {M_t.nnz} nonzeros")

    rows_ts, rows_t = np.asarray(M_ts.sum(axis=1)).ravel(), np.asarray(M_t.sum(axis=1)).ravel()
    row_error = np.max(np.abs(rows_ts - rows_t) / rows_t)
    print(f"row sums: max |M_ts 1 - M_t 1| / M_t 1 = {row_error:.3g}; total {rows_ts.sum():.17g} (area 1)")
    lumped_s = np.asarray(tetia.Remap(nonmortar, nonmortar, order=1).target_mass.sum(axis=1)).ravel()
    column_error = np.max(np.abs(np.asarray(M_ts.sum(axis=0)).ravel() - lumped_s) / lumped_s)
    print(f"column sums: max |1^T M_ts - lumped M_s| / lumped M_s = {column_error:.3g}")

    linear = 2.0 - nonmortar.points @ np.array([1.5, -0.25])
    projected = scipy.sparse.linalg.spsolve(M_t.tocsc(), M_ts @ linear)
    linear_error = np.max(np.abs(projected - (2.0 - mortar.points @ np.array([1.5, -0.25]))))
    constant_error = np.max(np.abs(coupling(np.ones(nonmortar.num_points)) - 1.0))
    print(f"mortar projection: max error on a constant {constant_error:.3g}, on a linear function "
          f"{linear_error:.3g}")
    assert row_error < 1e-12 and column_error < 1e-12 and abs(rows_ts.sum() - 1.0) < 1e-13
    assert constant_error < 1e-10 and linear_error < 1e-10
    print("mortar coupling: ok")


if __name__ == "__main__":
    main()
