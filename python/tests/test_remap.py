"""tetia.Remap: the CLI's numbers (bit for bit), conservation and linear reproduction on
unstructured meshes checked through SciPy, the matrices, vector fields, two threads, bad input."""

import json
import threading

import meshio
import numpy as np
import pytest
import scipy.sparse
import scipy.sparse.linalg

import tetia
from conftest import cube_points, delaunay_mesh, run_cli, square_points
from test_mesh import hex_grid
from test_supermesh import write_msh


def centroids(mesh):
    simplices = mesh.points[mesh.simplices]
    volume = np.abs(np.linalg.det(simplices[:, 1:] - simplices[:, :1]))
    cell = np.bincount(mesh.simplex_cell, volume, mesh.num_cells)
    return np.stack([np.bincount(mesh.simplex_cell, volume * simplices[:, :, d].mean(axis=1), mesh.num_cells) / cell
                     for d in range(mesh.points.shape[1])], axis=1)


@pytest.mark.parametrize("order", [0, 1])
def test_same_values_as_the_cli(tmp_path, cli, order):
    a, b = delaunay_mesh(cube_points(250, 31)), delaunay_mesh(cube_points(150, 32))
    rng = np.random.default_rng(33)
    u = rng.standard_normal(a.num_cells if order == 0 else a.num_points)
    data = {"cell_data": {"u": u}} if order == 0 else {"point_data": {"u": u}}
    pa, pb = write_msh(a, tmp_path / "a.msh", **data), write_msh(b, tmp_path / "b.msh")
    out = str(tmp_path / "out.vtu")
    summary = json.loads(run_cli(cli, "remap", pa, pb, "--field", "u", "--order", str(order), "-o", out, "--quiet"))
    result = meshio.read(out)
    expected = np.ravel(result.cell_data["u"][0] if order == 0 else result.point_data["u"])
    r = tetia.Remap(tetia.read_mesh(pa), tetia.read_mesh(pb), order=order)
    assert np.array_equal(r(u), expected)  # bit for bit
    assert r.intersection_volume == summary["intersection_volume"]


def test_p0_conservation_and_constants(cubes):
    source, target = cubes
    r = tetia.Remap(source, target, order=0)
    assert r.shape == (target.num_cells, source.num_cells)
    u = np.random.default_rng(1).standard_normal(source.num_cells)
    v = r(u)
    integral = source.volumes @ u
    assert abs(target.volumes @ v - integral) <= 1e-13 * np.abs(source.volumes * u).sum()
    assert np.allclose(r(np.full(source.num_cells, 3.25)), 3.25, rtol=1e-13, atol=0)
    # through SciPy: the operator, M and the target masses
    assert scipy.sparse.isspmatrix_csr(r.matrix) and r.matrix.shape == r.shape
    np.testing.assert_allclose(r.matrix @ u, v, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(np.asarray(r.mixed_mass.sum(axis=1)).ravel(), target.volumes, rtol=1e-12)
    np.testing.assert_allclose(np.asarray(r.mixed_mass.sum(axis=0)).ravel(), source.volumes, rtol=1e-12)
    np.testing.assert_allclose(r.target_mass.diagonal(), target.volumes, rtol=1e-15)
    np.testing.assert_allclose(r.coverage, 1.0, rtol=1e-12)


def test_p0_from_hexahedra_conserves_and_keeps_constants():
    points, cells = hex_grid(4, jitter=0.35, seed=4)
    source = tetia.Mesh(points, {"hexahedron": cells})
    target = delaunay_mesh(cube_points(120, 34))
    for a, b in ((source, target), (target, source)):
        r = tetia.Remap(a, b, order=0)
        assert r.shape == (b.num_cells, a.num_cells)  # hexahedra, not their tetrahedra
        u = 1.0 + centroids(a) @ np.array([2.0, -3.0, 0.5])
        v = r(u)
        assert abs(b.volumes @ v - a.volumes @ u) <= 1e-14 * (a.volumes @ np.abs(u))
        np.testing.assert_allclose(r(np.full(a.num_cells, -7.5)), -7.5, rtol=1e-13)  # the kernel: 1e-13 of the smaller cell
        np.testing.assert_allclose(r.mixed_mass @ u, b.volumes * v, rtol=1e-12)


@pytest.mark.parametrize("meshes", ["cubes", "squares"])
def test_p1_reproduces_linear_fields_and_conserves(request, meshes):
    source, target = request.getfixturevalue(meshes)
    dim = source.dim
    coefficients = np.array([0.75, -2.0, 1.5][:dim])
    u = 0.5 + source.points @ coefficients
    r = tetia.Remap(source, target, order=1)
    assert r.shape == (target.num_points, source.num_points)
    v, report = r.apply(u, report=True)
    assert report["iterations"] > 0 and report["residual"] <= 1e-12
    np.testing.assert_allclose(v, 0.5 + target.points @ coefficients, rtol=0, atol=1e-9)
    # the Galerkin projection: M_t v = M_ts u, and 1^T M_t v = 1^T M_ts u (conservation)
    M_ts, M_t = r.mixed_mass, r.target_mass
    assert scipy.sparse.isspmatrix_csr(M_ts) and M_t.shape == (target.num_points,) * 2
    np.testing.assert_allclose(M_t @ v, M_ts @ u, rtol=0, atol=1e-12)
    assert abs((M_t @ v).sum() - (M_ts @ u).sum()) < 1e-12
    # and SciPy's own solve of the same system agrees
    w, info = scipy.sparse.linalg.cg(M_t, M_ts @ u, tol=1e-14, atol=0)
    assert info == 0 and np.allclose(w, v, atol=1e-8)
    with pytest.raises(ValueError, match="order 1 has no sparse operator"):
        r.matrix


def test_vector_fields_are_remapped_component_by_component(squares):
    source, target = squares
    r = tetia.Remap(source, target, order=0, normalization="covered_volume")
    u = np.random.default_rng(2).standard_normal((source.num_cells, 3))
    v = r(u)
    assert v.shape == (target.num_cells, 3)
    for k in range(3):
        assert np.array_equal(v[:, k], r(np.ascontiguousarray(u[:, k])))
    assert np.array_equal(r(np.asfortranarray(u)), v)


@pytest.mark.parametrize("meshes", ["cubes", "squares"])
def test_remap_p1_from_the_meshes_is_the_operators_bit_for_bit(request, meshes):
    # tetia.remap_p1 keeps no supermesh (its pieces are summed into the loads as they are found);
    # the numbers are those of the operator that keeps it.
    source, target = request.getfixturevalue(meshes)
    rng = np.random.default_rng(5)
    r = tetia.Remap(source, target, order=1)
    for u in (rng.standard_normal(source.num_points), rng.standard_normal((source.num_points, 2))):
        for threads in (1, 2):
            v, report = tetia.remap_p1(source, target, u, threads=threads, report=True)
            expected, expected_report = r.apply(u, report=True)
            assert v.shape == expected.shape
            assert np.array_equal(v, expected)
            assert report == expected_report
    with pytest.raises(ValueError, match="one value per source node"):
        tetia.remap_p1(source, target, np.ones(source.num_points + 1))
    with pytest.raises(ValueError, match="finite"):
        tetia.remap_p1(source, target, np.full(source.num_points, np.nan))


def test_two_threads_at_once_get_what_one_gets(cubes):
    source, target = cubes
    r = tetia.Remap(source, target, order=1)
    fields = [np.random.default_rng(s).standard_normal(source.num_points) for s in range(8)]
    expected = [r(f) for f in fields]
    U = np.random.default_rng(9).standard_normal((20000, 4, 3))
    V = np.random.default_rng(10).standard_normal((20000, 4, 3))
    volumes = tetia.intersection_volume(U, V)
    results, errors = {}, []

    def work(name, items):
        try:
            results[name] = [r(f) for f in items] + [tetia.intersection_volume(U, V),
                                                     tetia.supermesh(source, target).intersection_volume]
        except Exception as error:  # pragma: no cover - reported below
            errors.append(error)

    threads = [threading.Thread(target=work, args=(n, fields)) for n in ("a", "b")]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for name in ("a", "b"):
        for got, want in zip(results[name], expected):
            assert np.array_equal(got, want)
        assert np.array_equal(results[name][-2], volumes)
        assert results[name][-1] == tetia.supermesh(source, target).intersection_volume


def test_the_operator_keeps_its_meshes():
    r = tetia.Remap(delaunay_mesh(square_points(40, 5)), delaunay_mesh(square_points(30, 6)), order=1)
    import gc

    gc.collect()
    u = r.source.points[:, 0].copy()
    np.testing.assert_allclose(r(u), r.target.points[:, 0], atol=1e-10)


def test_bad_fields_and_options_raise_value_error(cubes, squares):
    source, target = cubes
    r = tetia.Remap(source, target)
    with pytest.raises(ValueError, match=f"has 3 rows, but the source has {source.num_cells} cells"):
        r(np.zeros(3))
    with pytest.raises(ValueError, match=r"shape \(n,\) or \(n, k\)"):
        r(np.zeros((source.num_cells, 2, 2)))
    with pytest.raises(ValueError, match=r"field\[4\] is not finite"):
        r(np.where(np.arange(source.num_cells) == 4, np.nan, 1.0))
    with pytest.raises(ValueError, match="order must be 0 or 1"):
        tetia.Remap(source, target, order=2)
    with pytest.raises(ValueError, match="order must be 0 or 1"):
        tetia.Remap(source, target, order=True)
    with pytest.raises(ValueError, match="normalization must be"):
        tetia.Remap(source, target, normalization="none")
    with pytest.raises(ValueError, match="3D and the target mesh 2D"):
        tetia.Remap(source, squares[1])
