"""tetia.Remap's methods (lumped, bounded, discontinuous, linear): the CLI's numbers bit for bit,
conservation, bounds and linear reproduction on unstructured meshes, coverage, and the saved
operators read by SciPy and by netCDF4 (ESMF weight files) applied to fields."""

import json

import meshio
import numpy as np
import pytest
import scipy.io
import scipy.sparse

import tetia
from conftest import cube_points, delaunay_mesh, run_cli, square_points
from test_supermesh import write_msh


@pytest.fixture(scope="module")
def shifted():
    """Two unstructured meshes of the unit cube, the target shifted by 0.3 in x: partly covered."""
    return delaunay_mesh(cube_points(200, 41)), delaunay_mesh(cube_points(150, 42) + [0.3, 0.0, 0.0])


@pytest.fixture(scope="module")
def shifted2():
    return delaunay_mesh(square_points(200, 43)), delaunay_mesh(square_points(150, 44) + [0.3, 0.0])


def integral_p1(mesh, u):
    s = mesh.points[mesh.simplices]
    d = s.shape[1] - 1
    measure = np.abs(np.linalg.det(s[:, 1:] - s[:, :1])) / (6.0 if d == 3 else 2.0)
    return float(np.sum(measure * u[mesh.simplices].mean(axis=1)))


CASES = [  # (order, method, CLI flags, where the values are: source, target)
    (0, "standard", ["--order", "0"], "cells", "cells"),
    (0, "linear", ["--order", "0", "--reconstruct", "linear"], "cells", "cells"),
    (1, "standard", ["--order", "1"], "points", "points"),
    (1, "lumped", ["--order", "1", "--lumped"], "points", "points"),
    (1, "bounded", ["--order", "1", "--bounded"], "points", "points"),
    (1, "discontinuous", ["--order", "1", "--discontinuous"], "points", "cell_nodes"),
]


@pytest.mark.parametrize("order,method,flags,source_at,target_at", CASES)
def test_same_values_as_the_cli(tmp_path, cli, shifted, order, method, flags, source_at, target_at):
    a, b = shifted
    rng = np.random.default_rng(45)
    u = rng.standard_normal(a.num_cells if source_at == "cells" else a.num_points)
    data = {"cell_data": {"u": u}} if source_at == "cells" else {"point_data": {"u": u}}
    pa, pb = write_msh(a, tmp_path / "a.msh", **data), write_msh(b, tmp_path / "b.msh")
    out = str(tmp_path / "out.vtu")
    summary = json.loads(run_cli(cli, "remap", pa, pb, "--field", "u", *flags, "-o", out, "--quiet"))
    result = meshio.read(out)
    if target_at == "points":
        expected = np.ravel(result.point_data["u"])
    else:
        expected = np.ravel(result.cell_data["u"][0])  # cells, or (d + 1) values per simplex
    r = tetia.Remap(tetia.read_mesh(pa), tetia.read_mesh(pb), order=order, method=method)
    assert np.array_equal(r(u), expected)  # bit for bit
    assert summary["coverage"]["uncovered"] > 0
    coverage = np.ravel(result.cell_data["covered_fraction"][0])
    assert np.allclose(r.coverage, coverage, rtol=0, atol=1e-14)
    if target_at == "points":
        assert np.array_equal(r.node_coverage, np.ravel(result.point_data["node_covered_fraction"]))


@pytest.mark.parametrize("dim", [3, 2])
def test_conservation_bounds_and_linear_fields(request, dim):
    a, b = request.getfixturevalue("shifted" if dim == 3 else "shifted2")
    x = a.points
    step = (x[:, 0] + 0.3 * x[:, 1] > 0.55).astype(float)
    galerkin = tetia.Remap(a, b, order=1)
    for method in ("lumped", "bounded"):
        r = tetia.Remap(a, b, order=1, method=method)
        v = r(step)
        # conserved: the integral over the overlap, the loads' sum
        overlap = float(np.sum(galerkin.mixed_mass @ step))
        assert abs(integral_p1(b, v) - overlap) <= 1e-13 * abs(overlap)
        slack = 0.0 if method == "bounded" else 1e-14
        assert v.min() >= -slack and v.max() <= 1.0 + slack, method
    assert galerkin(step).min() < 0.0 or galerkin(step).max() > 1.0  # the test sees the overshoot
    # linear fields on meshes of one domain: bounded and discontinuous reproduce them (Galerkin's
    # solve spreads a partly covered target's deficit, so not on the shifted pair)
    a, b = request.getfixturevalue("cubes" if dim == 3 else "squares")

    def linear(p):
        return 1.0 + p[:, 0] + 2.0 * p[:, 1] + (3.0 * p[:, 2] if dim == 3 else 0.0)

    assert np.abs(tetia.Remap(a, b, order=1, method="bounded")(linear(a.points)) - linear(b.points)).max() < 1e-10
    dg = tetia.Remap(a, b, order=1, method="discontinuous")(linear(a.points)).reshape(-1, dim + 1)
    assert np.abs(dg - linear(b.points)[b.simplices]).max() < 1e-10


def test_methods_that_do_not_fit_the_order_are_errors(cubes):
    source, target = cubes
    for order, method in [(0, "lumped"), (0, "bounded"), (1, "linear"), (1, "quadratic")]:
        with pytest.raises(ValueError):
            tetia.Remap(source, target, order=order, method=method)
    with pytest.raises(ValueError):
        tetia.Remap(source, target, order=1, method="bounded").matrix
    with pytest.raises(ValueError):
        tetia.Remap(source, target, order=0).node_coverage


@pytest.mark.parametrize("flags", [["--order", "0"], ["--order", "1", "--lumped"], ["--order", "1", "--discontinuous"]])
def test_saved_operators_in_scipy_and_netcdf(tmp_path, cli, shifted, flags):
    netCDF4 = pytest.importorskip("netCDF4")
    a, b = shifted
    rng = np.random.default_rng(46)
    cells = flags[1] == "0"
    u = rng.standard_normal(a.num_cells if cells else a.num_points)
    pa = write_msh(a, tmp_path / "a.msh", **({"cell_data": {"u": u}} if cells else {"point_data": {"u": u}}))
    pb = write_msh(b, tmp_path / "b.msh")
    out = str(tmp_path / "out.vtu")
    for name in ("w.mtx", "w.nc"):
        run_cli(cli, "remap", pa, pb, "--field", "u", *flags, "-o", out, "--save-operator", str(tmp_path / name),
                "--quiet")
    result = meshio.read(out)
    expected = np.ravel(result.point_data["u"] if flags[-1] == "--lumped" else result.cell_data["u"][0])
    w = scipy.io.mmread(str(tmp_path / "w.mtx")).tocsr()
    assert np.allclose(w @ u, expected, rtol=0, atol=1e-13)
    with netCDF4.Dataset(str(tmp_path / "w.nc")) as nc:
        row, col, S = nc["row"][:], nc["col"][:], nc["S"][:]
        assert nc.dimensions["n_s"].size == w.nnz
        assert nc.dimensions["n_a"].size == w.shape[1] and nc.dimensions["n_b"].size == w.shape[0]
        esmf = scipy.sparse.csr_matrix((S, (row - 1, col - 1)), shape=w.shape)
        assert (esmf != w).nnz == 0  # the same weights, bit for bit
        assert nc.normalization == "destarea"
        frac_b, area_b = nc["frac_b"][:], nc["area_b"][:]
        # the target's measures: its volume, and the overlap's
        assert abs(area_b.sum() - b.volumes.sum()) <= 1e-12 * b.volumes.sum()
        overlap = tetia.supermesh(a, b).intersection_volume
        assert abs(float(np.sum(area_b * frac_b)) - overlap) <= 1e-12 * overlap
        if cells:
            assert np.allclose(frac_b, np.ravel(result.cell_data["covered_fraction"][0]), rtol=0, atol=1e-14)
            area_a, frac_a = nc["area_a"][:], nc["frac_a"][:]
            assert abs(float(np.sum(area_a * frac_a)) - overlap) <= 1e-12 * overlap
