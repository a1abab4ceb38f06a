#!/usr/bin/env python3
"""Accuracy, bounds and coverage of tetia's remap methods, through the CLI (`tetia remap`).

Measures, on unstructured meshes of the unit cube (3D) and the unit square (2D), each a
Delaunay triangulation of a jittered structured grid (source with 3n/2 cells per axis, target
with n; 3D n = 4, 8, 16, 2D n = 8, 16, 32, 64):

  1. for two smooth fields (sin(x) cos(y) exp(z), and a Gaussian bump; 2D without z), the error
     of every method at every size and the rate between sizes. P1, lumped, bounded and
     discontinuous P1: the CLI's relative_l2_error (L2 error against the expression, 64-point
     rule per tetrahedron, 16 per triangle). P0 and P0 with linear reconstruction: the relative
     discrete L2 error against the exact cell averages, sqrt(sum |T| (u_T - avg_T)^2) /
     sqrt(sum |T| avg_T^2), from the VTU, since the CLI's relative_l2_error of a P0 result contains the error of
     representing the field by constants (first order whatever the remap does). The largest
     conservation_error of each method over these runs too;
  2. a step (x + 0.3 y > 0.55) at the middle size: each method's least and largest value;
  3. a partly covered target (the middle target shifted by +0.3 in x): coverage counts,
     conservation, and whether --normalize covered reproduces a constant on partly covered cells.

Writes docs/figures/remap_methods_{step_2d,step_3d,convergence,coverage}.png and prints the
tables as Markdown (quoted in docs/remap.md). 116 runs of the CLI, under a minute on two cores.

Run from the repository root, after building the CLI:

  /usr/bin/python3 scripts/remap_methods_study.py [--out-dir docs/figures] [--cli build/tetia]
                                                  [--work-dir DIR]

Needs numpy, scipy, matplotlib and meshio.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402
import meshio  # noqa: E402
import numpy as np  # noqa: E402
import scipy.spatial  # noqa: E402
from matplotlib.colors import LinearSegmentedColormap  # noqa: E402

SIZES = {3: [4, 8, 16], 2: [8, 16, 32, 64]}
MIDDLE = {3: 8, 2: 32}
SHIFT = 0.3
ZOOM = ((0.85, 1.15), (0.35, 0.65))  # the coverage figure's window: the band of partly covered cells

FIELDS = {
    "f1": {3: "sin(x)*cos(y)*exp(z)", 2: "sin(x)*cos(y)"},
    "f2": {3: "exp(-20*((x-0.4)^2+(y-0.6)^2+(z-0.5)^2))", 2: "exp(-20*((x-0.4)^2+(y-0.6)^2))"},
}
STEP = "(x + 0.3*y > 0.55) ? 1 : 0"

# name -> CLI flags; "cells" marks the methods whose result is per cell (P0).
METHODS = {
    "P0": ["--order", "0"],
    "P0 linear": ["--order", "0", "--reconstruct", "linear"],
    "P1 Galerkin": ["--order", "1"],
    "P1 lumped": ["--order", "1", "--lumped"],
    "P1 bounded": ["--order", "1", "--bounded"],
    "P1 discontinuous": ["--order", "1", "--discontinuous"],
}
P0_METHODS = ("P0", "P0 linear")
STYLE = {"P0": ("#1f77b4", "o"), "P0 linear": ("#17becf", "s"), "P1 Galerkin": ("#d62728", "^"),
         "P1 lumped": ("#ff7f0e", "v"), "P1 bounded": ("#2ca02c", "D"), "P1 discontinuous": ("#9467bd", "x")}

# The step's color scale: a gray ramp over [0, 1] and color only outside it, so that any
# colored spot is an overshoot (red) or an undershoot (blue).
VMIN, VMAX = -0.25, 1.25
STEP_CMAP = LinearSegmentedColormap.from_list(
    "step", [(0.0, "#08306b"), (0.25 / 1.5, "#202020"), (1.25 / 1.5, "#e8e8e8"), (1.0, "#a50f15")])


# ---------------------------------------------------------------------------------------------
# Meshes


def jittered_delaunay(n, d, seed):
    """Delaunay triangulation of an (n+1)^d grid of the unit box, interior coordinates moved by
    up to 0.2 h. A coordinate on the boundary (0 or 1) is not moved, so boundary points slide
    only within their face or edge and the simplices fill the box exactly."""
    h = 1.0 / n
    axis = np.linspace(0.0, 1.0, n + 1)
    grid = np.stack(np.meshgrid(*([axis] * d), indexing="ij"), -1).reshape(-1, d)
    rng = np.random.default_rng(seed)
    jitter = rng.uniform(-0.2 * h, 0.2 * h, grid.shape)
    jitter[(grid == 0.0) | (grid == 1.0)] = 0.0
    points = grid + jitter
    cells = scipy.spatial.Delaunay(points).simplices.copy()
    vol = signed_volumes(points, cells)
    # Coplanar points on the box's faces can give Qhull flat simplices; they add nothing to the
    # covered measure but would be degenerate cells in the file.
    keep = np.abs(vol) >= 1e-12 * h**d
    dropped = int((~keep).sum())
    cells, vol = cells[keep], vol[keep]
    flip = vol < 0  # positive orientation, as Gmsh writes them
    cells[flip, 0], cells[flip, 1] = cells[flip, 1].copy(), cells[flip, 0].copy()
    total = np.abs(vol).sum()
    if abs(total - 1.0) > 1e-12:
        sys.exit(f"mesh n={n} d={d}: measure {total!r}, not 1")
    return points, cells, dropped


def signed_volumes(points, cells):
    edges = points[cells[:, 1:]] - points[cells[:, :1]]
    return np.linalg.det(edges) / math.factorial(points.shape[1])


def write_msh(path, points, cells):
    d = points.shape[1]
    pts = np.c_[points, np.zeros(len(points))] if d == 2 else points
    kind = "tetra" if d == 3 else "triangle"
    zeros = np.zeros(len(cells), dtype=int)  # tags, so that meshio does not warn about them
    mesh = meshio.Mesh(pts, [(kind, cells)], cell_data={"gmsh:physical": [zeros], "gmsh:geometrical": [zeros]})
    meshio.write(path, mesh, file_format="gmsh22", binary=False)


class Meshes:
    """The study's mesh files, written once into the work folder."""

    def __init__(self, work):
        self.work = work
        self.cache = {}
        self.cells = {}  # (d, n) -> (cells, flat simplices dropped)

    def path(self, d, n, shift=0.0):
        key = (d, n, shift)
        if key not in self.cache:
            points, cells, dropped = jittered_delaunay(n, d, seed=1000 * d + n)
            self.cells[(d, n)] = (len(cells), dropped)
            points = points + np.eye(d)[0] * shift
            name = os.path.join(self.work, f"box{d}d_n{n}" + (f"_shift{shift}" if shift else "") + ".msh")
            write_msh(name, points, cells)
            self.cache[key] = name
        return self.cache[key]

    def pair(self, d, n, shift=0.0):
        return self.path(d, (3 * n + 1) // 2), self.path(d, n, shift)


# ---------------------------------------------------------------------------------------------
# Running the CLI and reading its results


class Runner:
    def __init__(self, cli, work):
        self.cli, self.work, self.count = cli, work, 0

    def remap(self, source, target, expr, flags, vtu=False):
        """The JSON summary, and the VTU (meshio) if asked for."""
        cmd = [self.cli, "remap", source, target, "--expr", expr, "--quiet"] + flags
        out = os.path.join(self.work, "out.vtu")
        if vtu:
            cmd += ["-o", out, "--ascii"]
        self.count += 1
        done = subprocess.run(cmd, capture_output=True, text=True)
        if done.returncode != 0:
            sys.exit(f"{' '.join(cmd)}\nexit {done.returncode}: {done.stderr}")
        summary = json.loads(done.stdout.strip().splitlines()[-1])
        return summary, (meshio.read(out) if vtu else None)


def cell_measures(vtu):
    cells = vtu.cells[0].data
    d = cells.shape[1] - 1
    return np.abs(signed_volumes(vtu.points[:, :d], cells))


def cell_data(vtu, name):
    return np.asarray(vtu.cell_data[name][0])


def p0_discrete_error(vtu):
    """sqrt(sum |T| (u_T - avg_T)^2) / sqrt(sum |T| avg_T^2), avg_T the exact cell average."""
    w = cell_measures(vtu)
    u, exact = cell_data(vtu, "field"), cell_data(vtu, "exact")
    return math.sqrt(np.sum(w * (u - exact) ** 2) / np.sum(w * exact**2))


def result_values(vtu, method):
    """Every value the result has: cell values (P0), nodal values (P1), vertex values (DG)."""
    if method in P0_METHODS or method == "P1 discontinuous":
        return cell_data(vtu, "field").ravel()
    return np.asarray(vtu.point_data["field"])


def rates(errors, sizes):
    """log2 of the error ratio over log2 of the h ratio, between successive sizes."""
    return [math.log2(ea / eb) / math.log2(nb / na)
            for ea, eb, na, nb in zip(errors, errors[1:], sizes, sizes[1:])]


def fmt(x):
    if x == 0:
        return "0"
    return f"{x:.2e}".replace("e-0", "e-").replace("e+0", "e+")


# ---------------------------------------------------------------------------------------------
# The measurements


def convergence(meshes, runner):
    """errors[d][field][method] = list over SIZES[d]; conservation[method] = the largest."""
    errors, conservation = {}, {m: 0.0 for m in METHODS}
    for d in (3, 2):
        errors[d] = {}
        for field, exprs in FIELDS.items():
            errors[d][field] = {}
            for method, flags in METHODS.items():
                row = []
                for n in SIZES[d]:
                    source, target = meshes.pair(d, n)
                    p0 = method in P0_METHODS
                    summary, vtu = runner.remap(source, target, exprs[d], flags, vtu=p0)
                    row.append(p0_discrete_error(vtu) if p0 else summary["relative_l2_error"])
                    conservation[method] = max(conservation[method], abs(summary["conservation_error"]))
                errors[d][field][method] = row
    return errors, conservation


def step(meshes, runner, conservation):
    """ranges[d][method] = (least, largest); results[d][method] = the VTU, for the figures."""
    ranges, results = {}, {}
    for d in (3, 2):
        ranges[d], results[d] = {}, {}
        source, target = meshes.pair(d, MIDDLE[d])
        for method, flags in METHODS.items():
            summary, vtu = runner.remap(source, target, STEP, flags, vtu=True)
            values = result_values(vtu, method)
            ranges[d][method] = (float(values.min()), float(values.max()))
            results[d][method] = vtu
            conservation[method] = max(conservation[method], abs(summary["conservation_error"]))
    return ranges, results


COVERAGE_CASES = [
    ("P0", "full", ["--order", "0", "--normalize", "full"]),
    ("P0", "covered", ["--order", "0", "--normalize", "covered"]),
    ("P1 Galerkin", "", ["--order", "1"]),
    ("P1 lumped", "full", ["--order", "1", "--lumped", "--normalize", "full"]),
    ("P1 lumped", "covered", ["--order", "1", "--lumped", "--normalize", "covered"]),
    ("P1 bounded", "", ["--order", "1", "--bounded"]),
]


def coverage(meshes, runner):
    """rows[d] = list of dicts; constants[(method, normalize)] = the 2D VTU of the field 1."""
    rows, constants = {}, {}
    for d in (3, 2):
        rows[d] = []
        source, target = meshes.pair(d, MIDDLE[d], shift=SHIFT)
        for method, normalize, flags in COVERAGE_CASES:
            summary, vtu = runner.remap(source, target, FIELDS["f1"][d], flags, vtu=True)
            cov = summary["coverage"]
            # least_fraction counts the uncovered ones (0); the least of those the source touches
            # says how small a covered part the covered normalization divides by.
            fraction = (cell_data(vtu, "covered_fraction") if cov["of"] == "cells"
                        else np.asarray(vtu.point_data["node_covered_fraction"]))
            row = {"method": method, "normalize": normalize or "-", "of": cov["of"],
                   "uncovered": cov["uncovered"], "partly_covered": cov["partly_covered"],
                   "least_fraction": cov["least_fraction"], "least_positive": float(fraction[fraction > 0].min()),
                   "conservation_error": summary["conservation_error"], "const_error": None}
            if normalize:
                # A constant 1 on every cell (node) the source touches: reproduced only if the
                # average is taken over the covered measure.
                _, vtu = runner.remap(source, target, "1", flags, vtu=True)
                if method == "P0":
                    touched = cell_data(vtu, "covered_fraction") > 0
                    u = cell_data(vtu, "field")
                else:
                    touched = np.asarray(vtu.point_data["node_covered_fraction"]) > 0
                    u = np.asarray(vtu.point_data["field"])
                row["const_error"] = float(np.abs(u[touched] - 1.0).max())
                if d == 2 and method == "P0":
                    constants[normalize] = vtu
            rows[d].append(row)
    return rows, constants


# ---------------------------------------------------------------------------------------------
# Figures


def triangulation(vtu):
    return mtri.Triangulation(vtu.points[:, 0], vtu.points[:, 1], vtu.cells[0].data)


def draw_2d(ax, vtu, method, **kw):
    tri = triangulation(vtu)
    if method in P0_METHODS:
        return ax.tripcolor(tri, facecolors=cell_data(vtu, "field"), shading="flat", **kw)
    if method == "P1 discontinuous":
        # Each triangle with its own three vertex values: a triangulation of unshared vertices.
        cells = vtu.cells[0].data
        xy = vtu.points[cells.ravel(), :2]
        own = mtri.Triangulation(xy[:, 0], xy[:, 1], np.arange(3 * len(cells)).reshape(-1, 3))
        return ax.tripcolor(own, cell_data(vtu, "field").ravel(), shading="gouraud", **kw)
    return ax.tripcolor(tri, np.asarray(vtu.point_data["field"]), shading="gouraud", **kw)


def section_3d(vtu, method, z=0.5, pixels=240):
    """The result on the plane z = 0.5 exactly, on a pixels^2 raster: each pixel's tetrahedron
    found by its barycentric coordinates, and the method's function evaluated there (P0: the
    cell value; P1: the nodal values interpolated; discontinuous P1: the cell's own vertex
    values interpolated). A true section, so that overshoot inside a cell shows as it is."""
    pts, cells = vtu.points, vtu.cells[0].data
    zs = pts[cells, 2]
    crossing = np.nonzero((zs.min(1) <= z) & (zs.max(1) >= z))[0]
    c = (np.arange(pixels) + 0.5) / pixels
    px, py = np.meshgrid(c, c, indexing="xy")
    image = np.full(px.shape, np.nan)
    if method in P0_METHODS:
        values = cell_data(vtu, "field")
    elif method == "P1 discontinuous":
        values = cell_data(vtu, "field")  # (cells, 4), in the order of the cell's nodes
    else:
        values = np.asarray(vtu.point_data["field"])
    for t in crossing:
        v = pts[cells[t]]
        lo, hi = v[:, :2].min(0), v[:, :2].max(0)
        i0, i1 = np.searchsorted(c, lo[1]), np.searchsorted(c, hi[1], side="right")
        j0, j1 = np.searchsorted(c, lo[0]), np.searchsorted(c, hi[0], side="right")
        if i0 >= i1 or j0 >= j1:
            continue
        q = np.stack([px[i0:i1, j0:j1], py[i0:i1, j0:j1], np.full((i1 - i0, j1 - j0), z)], -1)
        a = (v[1:] - v[0]).T
        lam = np.linalg.solve(a, (q - v[0]).reshape(-1, 3).T).T
        bary = np.c_[1.0 - lam.sum(1), lam]
        inside = (bary >= -1e-12).all(1)
        if not inside.any():
            continue
        if method in P0_METHODS:
            val = np.full(len(bary), values[t])
        elif method == "P1 discontinuous":
            val = bary @ values[t]
        else:
            val = bary @ values[cells[t]]
        block = image[i0:i1, j0:j1].reshape(-1)
        block[inside] = val[inside]
        image[i0:i1, j0:j1] = block.reshape(i1 - i0, j1 - j0)
    return image


def figure_step(results, ranges, d, path):
    fig, axes = plt.subplots(2, 3, figsize=(11, 7.4), constrained_layout=True)
    for ax, method in zip(axes.ravel(), METHODS):
        vtu = results[d][method]
        if d == 2:
            art = draw_2d(ax, vtu, method, cmap=STEP_CMAP, vmin=VMIN, vmax=VMAX)
        else:
            art = ax.imshow(section_3d(vtu, method), origin="lower", extent=(0, 1, 0, 1), cmap=STEP_CMAP,
                            vmin=VMIN, vmax=VMAX, interpolation="nearest")
        lo, hi = ranges[d][method]
        ax.set_title(f"{method}\n[{lo:.3f}, {hi:.3f}]", fontsize=10)
        ax.set_aspect("equal")
        ax.set_xlim(0, 1)
        ax.set_ylim(0, 1)
        ax.set_xticks([0, 0.5, 1])
        ax.set_yticks([0, 0.5, 1])
    fig.colorbar(art, ax=axes, shrink=0.8, label="value (gray: within [0, 1]; blue below, red above)")
    n = MIDDLE[d]
    where = "unit square" if d == 2 else "unit cube, section z = 0.5"
    fig.suptitle(f"Step (x + 0.3 y > 0.55), {d}D, {where}: source n = {(3 * n + 1) // 2}, target n = {n} "
                 f"(jittered Delaunay)", fontsize=11)
    fig.savefig(path, dpi=150)
    plt.close(fig)


def figure_convergence(errors, path):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), constrained_layout=True)
    for ax, d in zip(axes, (3, 2)):
        h = np.array([1.0 / n for n in SIZES[d]])
        for method in METHODS:
            color, marker = STYLE[method]
            ax.loglog(h, errors[d]["f1"][method], marker=marker, color=color, label=method)
        # Reference slopes, below the P0 and P1 Galerkin lines so as not to hide them.
        for slope, anchor, ls in ((1, 0.5 * errors[d]["f1"]["P0"][0], ":"),
                                  (2, 0.5 * errors[d]["f1"]["P1 Galerkin"][0], "--")):
            ax.loglog(h, anchor * (h / h[0]) ** slope, ls, color="gray", lw=1, label=f"slope {slope}")
        ax.set_xlabel("target h = 1/n")
        ax.set_ylabel("relative L2 error")
        ax.set_title(f"{d}D: " + FIELDS["f1"][d], fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("P0, P0 linear: discrete L2 error of the cell averages; P1 methods: L2 error against the field",
                 fontsize=10)
    fig.savefig(path, dpi=150)
    plt.close(fig)


def figure_coverage(constants, path):
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.6), constrained_layout=True)
    full, covered = constants["full"], constants["covered"]
    tri = triangulation(full)
    panels = [
        (cell_data(full, "covered_fraction"), "covered_fraction", "viridis", 0, 1),
        (cell_data(full, "field"), "P0 of the field 1, --normalize full", "viridis", 0, 1),
        (cell_data(covered, "field"), "P0 of the field 1, --normalize covered", "viridis", 0, 1),
    ]
    for ax, (values, title, cmap, lo, hi) in zip(axes, panels):
        art = ax.tripcolor(tri, facecolors=values, shading="flat", cmap=cmap, vmin=lo, vmax=hi)
        ax.plot([0, 1, 1, 0, 0], [0, 0, 1, 1, 0], color="red", lw=1)
        ax.set_title(title, fontsize=10)
        ax.set_aspect("equal")
        ax.set_xlim(*ZOOM[0])
        ax.set_ylim(*ZOOM[1])
    fig.colorbar(art, ax=axes, shrink=0.85)
    n = MIDDLE[2]
    fig.suptitle(f"2D target (n = {n}) shifted by +{SHIFT} in x over the source (n = {(3 * n + 1) // 2}); "
                 f"the window [{ZOOM[0][0]}, {ZOOM[0][1]}] x [{ZOOM[1][0]}, {ZOOM[1][1]}] around the source's "
                 f"edge x = 1 (red)", fontsize=10)
    fig.savefig(path, dpi=150)
    plt.close(fig)


# ---------------------------------------------------------------------------------------------
# Tables


def print_tables(meshes, errors, conservation, ranges, cover, seconds, runs):
    print("Meshes (cells; flat simplices dropped)\n")
    print("| d | target n | target cells | source n | source cells |\n|---|---|---|---|---|")
    for d in (3, 2):
        for n in SIZES[d]:
            m = (3 * n + 1) // 2
            (tc, td), (sc, sd) = meshes.cells[(d, n)], meshes.cells[(d, m)]
            drop = lambda k: f" ({k} dropped)" if k else ""  # noqa: E731
            print(f"| {d} | {n} | {tc}{drop(td)} | {m} | {sc}{drop(sd)} |")
    for d in (3, 2):
        sizes = SIZES[d]
        for field in FIELDS:
            print(f"\n{d}D, {field} = {FIELDS[field][d]}; relative L2 error (P0, P0 linear: of the cell "
                  f"averages)\n")
            head = ["method"] + [f"n={n}" for n in sizes] + [f"rate {a}-{b}" for a, b in zip(sizes, sizes[1:])]
            print("| " + " | ".join(head) + " |")
            print("|" + "---|" * len(head))
            for method in METHODS:
                e = errors[d][field][method]
                print("| " + " | ".join([method] + [fmt(x) for x in e] + [f"{r:.2f}" for r in rates(e, sizes)]) + " |")
    print("\nLargest conservation_error over the runs above and the step (same domain)\n")
    print("| method | conservation_error |\n|---|---|")
    for method in METHODS:
        print(f"| {method} | {fmt(conservation[method])} |")
    print(f"\nStep {STEP}: least and largest value (P0: cells; P1: nodes; discontinuous: every cell "
          f"vertex); 3D n = {MIDDLE[3]}, 2D n = {MIDDLE[2]}\n")
    print("| method | 3D least | 3D largest | 2D least | 2D largest |\n|---|---|---|---|---|")
    for method in METHODS:
        (a, b), (c, e) = ranges[3][method], ranges[2][method]
        print(f"| {method} | {a:.4f} | {b:.4f} | {c:.4f} | {e:.4f} |")
    for d in (3, 2):
        print(f"\nPartly covered: {d}D target n = {MIDDLE[d]} shifted by +{SHIFT} in x, field {FIELDS['f1'][d]}; "
              f"max |u - 1|: the field 1 on the cells (nodes) the source touches\n")
        print("| method | normalize | of | uncovered | partly covered | least fraction | least positive | "
              "conservation_error | max abs(u - 1) |\n|---|---|---|---|---|---|---|---|---|")
        for r in cover[d]:
            const = "" if r["const_error"] is None else fmt(r["const_error"])
            print(f"| {r['method']} | {r['normalize']} | {r['of']} | {r['uncovered']} | {r['partly_covered']} | "
                  f"{fmt(r['least_fraction'])} | {fmt(r['least_positive'])} | "
                  f"{fmt(abs(r['conservation_error']))} | {const} |")
    print(f"\n{runs} runs of tetia remap, {seconds:.0f} s.")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out-dir", default="docs/figures", help="where the PNG files go")
    parser.add_argument("--cli", default="build/tetia", help="the tetia executable")
    parser.add_argument("--work-dir", help="keep the meshes and the last VTU here (default: a temporary folder)")
    args = parser.parse_args()
    if not os.access(args.cli, os.X_OK):
        sys.exit(f"{args.cli}: not an executable (build the CLI first, or pass --cli)")
    os.makedirs(args.out_dir, exist_ok=True)
    start = time.time()
    with tempfile.TemporaryDirectory() as tmp:
        work = args.work_dir or tmp
        os.makedirs(work, exist_ok=True)
        meshes, runner = Meshes(work), Runner(os.path.abspath(args.cli), work)
        errors, conservation = convergence(meshes, runner)
        ranges, results = step(meshes, runner, conservation)
        cover, constants = coverage(meshes, runner)
        figure_step(results, ranges, 2, os.path.join(args.out_dir, "remap_methods_step_2d.png"))
        figure_step(results, ranges, 3, os.path.join(args.out_dir, "remap_methods_step_3d.png"))
        figure_convergence(errors, os.path.join(args.out_dir, "remap_methods_convergence.png"))
        figure_coverage(constants, os.path.join(args.out_dir, "remap_methods_coverage.png"))
    print_tables(meshes, errors, conservation, ranges, cover, time.time() - start, runner.count)


if __name__ == "__main__":
    main()
