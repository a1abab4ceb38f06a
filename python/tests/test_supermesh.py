"""tetia.supermesh: what `tetia supermesh` computes on the same files (bit for bit), per cell
given, and the properties a supermesh must have: volume conserved, symmetric, pairs complete."""

import json

import meshio
import numpy as np
import pytest

import tetia
from conftest import cube_points, delaunay_mesh, run_cli, square_points
from test_mesh import hex_grid


def write_msh(mesh, path, **data):
    meshio.write(str(path), mesh.to_meshio(**data), file_format="gmsh22", binary=False)
    return str(path)


@pytest.mark.parametrize("dim", [3, 2])
def test_same_numbers_as_the_cli(tmp_path, cli, dim):
    if dim == 3:
        a, b = delaunay_mesh(cube_points(300, 21)), delaunay_mesh(cube_points(150, 22, lo=0.25, hi=1.25))
    else:
        a, b = delaunay_mesh(square_points(300, 23)), delaunay_mesh(square_points(150, 24, lo=0.25, hi=1.25))
    pa, pb = write_msh(a, tmp_path / "a.msh"), write_msh(b, tmp_path / "b.msh")
    summary = json.loads(run_cli(cli, "supermesh", pa, pb, "--quiet"))
    s = tetia.supermesh(tetia.read_mesh(pa), tetia.read_mesh(pb))
    key = "intersection_volume" if dim == 3 else "intersection_area"
    assert s.intersection_volume == summary[key]  # bit for bit (17 digits)
    assert len(s) == summary["pairs"] and s.candidates == summary["candidates"]
    # the meshes from arrays and from the files are the same meshes, in the same order
    t = tetia.supermesh(a, b)
    assert t.intersection_volume == s.intersection_volume
    assert np.array_equal(t.volume, s.volume) and np.array_equal(t.source_cell, s.source_cell)


def test_per_cell_given_and_conservation(cubes):
    source, target = cubes
    s = tetia.supermesh(source, target)
    assert s.source_cell.dtype == np.int64 and s.volume.shape == s.target_cell.shape == (len(s),)
    assert s.centroid.shape == (len(s), 3)
    # both meshes fill the unit cube: every cell is covered by its pairs
    np.testing.assert_allclose(np.bincount(s.source_cell, s.volume, source.num_cells), source.volumes,
                               rtol=1e-12, atol=0)
    np.testing.assert_allclose(np.bincount(s.target_cell, s.volume, target.num_cells), target.volumes,
                               rtol=1e-12, atol=0)
    assert abs(s.intersection_volume - 1.0) < 1e-13
    # sorted by target, pairs unique
    assert np.all(np.diff(s.target_cell) >= 0)
    assert len(set(zip(s.source_cell.tolist(), s.target_cell.tolist()))) == len(s)
    # the centroids integrate x: sum of volume * centroid = the cube's first moment
    np.testing.assert_allclose(s.volume @ s.centroid, [0.5, 0.5, 0.5], rtol=1e-12)


def test_symmetric_and_searches_agree(squares):
    source, target = squares
    s = tetia.supermesh(source, target)
    r = tetia.supermesh(target, source, search="rtree", threads=1)
    assert s.centroid.shape == (len(s), 2) and np.array_equal(s.area, s.volume)
    forward = dict(zip(zip(s.source_cell.tolist(), s.target_cell.tolist()), s.volume.tolist()))
    backward = dict(zip(zip(r.target_cell.tolist(), r.source_cell.tolist()), r.volume.tolist()))
    assert forward.keys() == backward.keys()
    scale = min(source.volumes.min(), target.volumes.min())
    assert max(abs(forward[k] - backward[k]) for k in forward) <= 1e-13 * scale * 10


def test_hexahedra_are_one_cell_each():
    points, cells = hex_grid(3, jitter=0.4, seed=3)
    hexes = tetia.Mesh(points, {"hexahedron": cells})
    tets = delaunay_mesh(cube_points(80, 25))
    s = tetia.supermesh(hexes, tets)
    assert s.source_cell.max() == hexes.num_cells - 1
    np.testing.assert_allclose(np.bincount(s.source_cell, s.volume, hexes.num_cells), hexes.volumes, rtol=1e-12)
    assert s.pieces >= len(s)


def test_meshio_meshes_are_accepted_and_bad_arguments_refused(cubes, squares):
    source, target = cubes
    s = tetia.supermesh(source.to_meshio(), target)
    assert s.intersection_volume == tetia.supermesh(source, target).intersection_volume
    with pytest.raises(ValueError, match="source mesh is 3D and the target mesh 2D"):
        tetia.supermesh(source, squares[0])
    with pytest.raises(ValueError, match='search must be "front" or "rtree"'):
        tetia.supermesh(source, target, search="brute")
    with pytest.raises(ValueError, match="threads must be None"):
        tetia.supermesh(source, target, threads=0)
    with pytest.raises(TypeError, match="tetia.Mesh or a meshio.Mesh"):
        tetia.supermesh(source, np.zeros((4, 3)))
