#!/usr/bin/env python3
"""Remap a cell field between two meshes read with meshio, and plot a slice of both.

    /usr/bin/python3 examples/python/remap_meshio.py [SOURCE TARGET] [-o slice.png]

SOURCE and TARGET are mesh files meshio reads (VTU, XDMF, Exodus, MED, Gmsh ...) of one
dimension; SOURCE's first cell field is remapped if it has one, else f(x, y, z) =
sin(3x) cos(2y) + z. Without files, two non-matching unstructured meshes of the unit cube are
made first (Delaunay tetrahedra of random points, written as VTU and XDMF). The script prints
the integrals of the field on both meshes (conservation), writes the target mesh with the
remapped field next to the PNG, and draws the cells of both meshes that the plane z = 0.5 cuts,
coloured by their values, side by side.
"""

import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import meshio  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from scipy.spatial import Delaunay  # noqa: E402

import tetia  # noqa: E402


def f(x):
    return np.sin(3 * x[:, 0]) * np.cos(2 * x[:, 1]) + x[:, 2]


def make_example_meshes(folder):
    """Two meshes of the unit cube that do not match, as a user would have them: files."""
    paths = []
    for seed, n, extension in ((1, 4000, "vtu"), (2, 1500, "xdmf")):
        rng = np.random.default_rng(seed)
        corners = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], dtype=float)
        points = np.vstack([corners, rng.random((n, 3))])
        path = os.path.join(folder, f"example_{'source' if seed == 1 else 'target'}.{extension}")
        meshio.write(path, meshio.Mesh(points, [("tetra", Delaunay(points).simplices)]))
        paths.append(path)
    return paths


def cell_centroids(mesh):
    """Each cell's centroid (volume-weighted over its simplices, for hexahedra and the like)."""
    s = mesh.points[mesh.simplices]
    volume = np.abs(np.linalg.det(s[:, 1:] - s[:, :1])) / 6
    weight = np.bincount(mesh.simplex_cell, volume, mesh.num_cells)
    return np.stack([np.bincount(mesh.simplex_cell, volume * s[:, :, d].mean(axis=1), mesh.num_cells) / weight
                     for d in range(3)], axis=1)


def slice_polygons(mesh, values, z):
    """The polygons in which the plane at height z cuts the mesh's tetrahedra, with the value
    of the cell each belongs to."""
    tets = mesh.points[mesh.simplices]
    polygons, colours = [], []
    for t, cell in zip(tets, mesh.simplex_cell):
        if not (t[:, 2].min() < z < t[:, 2].max()):
            continue
        cut = []
        for a in range(4):
            for b in range(a + 1, 4):
                za, zb = t[a, 2], t[b, 2]
                if (za - z) * (zb - z) < 0:
                    w = (z - za) / (zb - za)
                    cut.append(t[a, :2] + w * (t[b, :2] - t[a, :2]))
        cut = np.array(cut)
        centre = cut.mean(axis=0)
        order = np.argsort(np.arctan2(cut[:, 1] - centre[1], cut[:, 0] - centre[0]))
        polygons.append(cut[order])
        colours.append(values[cell])
    return polygons, np.array(colours)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    parser.add_argument("files", nargs="*", help="SOURCE TARGET (meshio formats)")
    parser.add_argument("-o", "--output", default="remap_slice.png", help="the PNG to write")
    args = parser.parse_args()
    if len(args.files) not in (0, 2):
        parser.error("give two mesh files, or none for the example meshes")
    folder = os.path.dirname(os.path.abspath(args.output))
    source_path, target_path = args.files or make_example_meshes(folder)

    source_meshio = meshio.read(source_path)
    source = tetia.Mesh.from_meshio(source_meshio, name=source_path)
    target = tetia.Mesh.from_meshio(meshio.read(target_path), name=target_path)
    if source.dim != 3:
        sys.exit("remap_meshio.py: this example slices 3D meshes")
    if source.cell_data:
        name, u = next(iter(source.cell_data.items()))
        u = np.asarray(u, dtype=float).reshape(source.num_cells, -1)[:, 0]
    else:
        name, u = "f", f(cell_centroids(source))

    remap = tetia.Remap(source, target, order=0)  # built once: the supermesh and the weights
    v = remap(u)                                  # applied to a field (as many as wanted)
    print(f"{source_path}: {source.num_cells} cells; {target_path}: {target.num_cells} cells; "
          f"{remap.matrix.nnz} overlapping pairs")
    print(f"integral of {name}: source {source.volumes @ u:.17g}, target {target.volumes @ v:.17g} "
          f"(overlap volume {remap.intersection_volume:.17g})")
    print(f"target cells covered: {np.count_nonzero(remap.coverage > 1 - 1e-12)} of {target.num_cells}")

    result = os.path.splitext(args.output)[0] + "_target.vtu"
    meshio.write(result, target.to_meshio(cell_data={name: v}))

    fig, axes = plt.subplots(1, 2, figsize=(11, 5), constrained_layout=True)
    lo, hi = min(u.min(), v.min()), max(u.max(), v.max())
    for ax, mesh, values, title in ((axes[0], source, u, "source"), (axes[1], target, v, "remapped (P0)")):
        polygons, colours = slice_polygons(mesh, values, 0.5)
        collection = PolyCollection(polygons, array=colours, cmap="viridis", edgecolors="k", linewidths=0.1)
        collection.set_clim(lo, hi)
        ax.add_collection(collection)
        ax.set_xlim(mesh.points[:, 0].min(), mesh.points[:, 0].max())
        ax.set_ylim(mesh.points[:, 1].min(), mesh.points[:, 1].max())
        ax.set_aspect("equal")
        ax.set_title(f"{title}: {mesh.num_cells} cells, slice z = 0.5")
    fig.colorbar(collection, ax=axes, label=name)
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output} and {result}")


if __name__ == "__main__":
    main()
