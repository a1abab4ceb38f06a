"""tetia.Mesh from arrays, files and meshio: cells of every type, results in the order given,
round trips through meshio's formats and tetia's .msh reader, and the errors bad input gets."""

import os
import warnings

import meshio
import numpy as np
import pytest

import tetia
from conftest import cube_points, delaunay_mesh, square_points

UNIT_CUBE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
                     dtype=float)


def hex_grid(n, jitter=0.0, seed=0):
    """n^3 hexahedra of the unit cube (interior nodes moved by jitter: not a structured geometry)."""
    g = np.linspace(0, 1, n + 1)
    x, y, z = np.meshgrid(g, g, g, indexing="ij")
    points = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    inner = np.all((points > 0) & (points < 1), axis=1)
    points[inner] += jitter / n * np.random.default_rng(seed).uniform(-1, 1, (inner.sum(), 3))
    idx = np.arange((n + 1) ** 3).reshape(n + 1, n + 1, n + 1)
    cells = []
    for i in range(n):
        for j in range(n):
            for k in range(n):
                cells.append([idx[i, j, k], idx[i + 1, j, k], idx[i + 1, j + 1, k], idx[i, j + 1, k],
                              idx[i, j, k + 1], idx[i + 1, j, k + 1], idx[i + 1, j + 1, k + 1], idx[i, j + 1, k + 1]])
    return points, np.array(cells)


def test_tetrahedra_from_a_bare_array():
    points = cube_points(100, 5)
    m = delaunay_mesh(points)
    assert m.dim == 3 and m.num_points == len(points) and m.num_cells == len(m.cells[0][1])
    assert m.cells[0][0] == "tetra"
    assert abs(m.volumes.sum() - 1.0) < 1e-14
    tets = points[m.cells[0][1]]
    assert np.allclose(m.volumes, np.abs(np.linalg.det(tets[:, 1:] - tets[:, :1])) / 6, rtol=1e-13, atol=0)


def test_inverted_cells_are_reoriented_and_counted():
    points = cube_points(50, 6)
    m = delaunay_mesh(points)
    cells = m.cells[0][1].copy()
    cells[::2] = cells[::2, [1, 0, 2, 3]]
    flipped = tetia.Mesh(points, cells)
    tets = points[cells]
    assert flipped.reoriented_cells == np.count_nonzero(np.linalg.det(tets[:, 1:] - tets[:, :1]) < 0) > 0
    assert np.allclose(flipped.volumes, m.volumes, rtol=1e-14, atol=0)
    assert np.array_equal(flipped.cells[0][1], cells)  # the cells as given


def test_every_3d_cell_type_in_the_order_given():
    points = np.vstack([UNIT_CUBE, [[0.5, 0.5, 2.0], [2, 0, 0], [2, 1, 0], [2, 0, 1], [2, 1, 1]]])
    cells = [("wedge", [[1, 9, 10, 5, 11, 12]]),           # x in [1, 2]: the prism (volume 0.5)
             ("hexahedron", [list(range(8))]),              # the unit cube
             ("pyramid", [[4, 5, 6, 7, 8]])]                # on the cube's top face: 1/3
    m = tetia.Mesh(points, cells)
    assert m.num_cells == 3
    assert np.allclose(m.volumes, [0.5, 1.0, 1.0 / 3.0], rtol=1e-15)
    assert list(m.cell_types) == ["wedge", "hexahedron", "pyramid"]
    assert np.array_equal(np.bincount(m.simplex_cell), [3, 6, 2])
    as_dict = tetia.Mesh(points, {"wedge": cells[0][1], "hexahedron": cells[1][1], "pyramid": cells[2][1]})
    assert np.array_equal(as_dict.volumes, m.volumes)


def test_2d_cells_with_two_or_three_coordinates():
    points2 = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0], [2, 1]], dtype=float)
    cells = {"quad": [[0, 1, 2, 3]], "triangle": [[1, 4, 5], [1, 5, 2]]}
    m2 = tetia.Mesh(points2, cells)
    assert m2.dim == 2 and np.allclose(m2.volumes, [1.0, 0.5, 0.5])
    points3 = np.hstack([points2, np.full((6, 1), 3.5)])
    m3 = tetia.Mesh(points3, cells)
    assert m3.dim == 2 and np.array_equal(m3.volumes, m2.volumes)
    assert tetia.Mesh(points2, np.array([[0, 1, 2, 3]])).cells[0][0] == "quad"  # 4 nodes, 2D points
    off_plane = points3.copy()
    off_plane[4, 2] = 4.0
    with pytest.raises(ValueError, match="plane"):
        tetia.Mesh(off_plane, cells)


@pytest.mark.parametrize("points, cells, message", [
    (UNIT_CUBE, [[0, 1, 3, 8]], "cell 0 .*node index 8 out of range"),
    (UNIT_CUBE, [[0, 1, 3, -1]], "node index -1 out of range"),
    (UNIT_CUBE, [[0, 1, 3, 4], [0, 1, 3, 3]], "cell 1: repeated node"),
    (np.where(np.arange(24).reshape(8, 3) == 5, np.nan, UNIT_CUBE), [[0, 1, 3, 4]], "node 1: coordinate 2 is not finite"),
    (UNIT_CUBE, np.array([[0.0, 1.0, 3.0, 4.0]]), "integer dtype"),
    (UNIT_CUBE, {"polygon": [[0, 1, 2]]}, "'polygon' is not one tetia reads"),
    (UNIT_CUBE, {"tetra": [[0, 1, 3, 4]], "triangle": [[0, 1, 2]]}, "2D and 3D cells mixed"),
    (UNIT_CUBE, {"tetra": [[0, 1, 3]]}, r"expected shape \(m, 4\)"),
    (UNIT_CUBE[:, :2], {"tetra": [[0, 1, 3, 4]]}, r"needs points of shape \(n, 3\)"),
    (UNIT_CUBE[:, :1], [[0, 1, 3]], r"points must have shape \(n, 3\) or \(n, 2\)"),
    (UNIT_CUBE, np.zeros((2, 7), dtype=int), "cells of 7 nodes"),
    (UNIT_CUBE, {}, "no cells"),
])
def test_bad_arrays_raise_value_error(points, cells, message):
    with pytest.raises(ValueError, match=message):
        tetia.Mesh(points, cells)


def test_flat_cells_are_kept_and_counted():
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0]], dtype=float)
    m = tetia.Mesh(points, [[0, 1, 2, 3], [0, 1, 2, 4]])  # the second has four nodes in a plane
    assert m.flat_cells == 1 and m.volumes[1] == 0.0
    other = tetia.Mesh(points[:4], [[0, 1, 2, 3]])
    assert tetia.supermesh(m, other).intersection_volume == 1 / 6


def test_the_mesh_keeps_its_own_copy():
    points = cube_points(30, 9)
    m = delaunay_mesh(points)
    points[:] = 0.0
    assert m.points.max() == 1.0 and not m.points.flags.writeable
    with pytest.raises(ValueError):
        m.points[0, 0] = 3.0


@pytest.mark.parametrize("extension, options", [
    (".vtu", {}), (".vtk", {}), (".xdmf", {}), (".msh", {"file_format": "gmsh22", "binary": False}),
    (".msh", {"file_format": "gmsh22", "binary": True}),
])
def test_meshio_round_trips(tmp_path, extension, options):
    points, cells = hex_grid(3, jitter=0.3)
    extra = np.vstack([points, [[0.5, 0.5, 1.5]]])
    top = np.flatnonzero(np.isclose(points[:, 2], 1.0))
    m = tetia.Mesh(extra, {"hexahedron": cells, "pyramid": [[top[0], top[3], top[15], top[12], len(points)]]})
    u = np.arange(m.num_cells, dtype=float) + 0.25
    path = str(tmp_path / f"mesh{extension}")
    meshio.write(path, m.to_meshio(cell_data={"u": u}), **options)
    back = tetia.read_mesh(path)
    assert back.dim == 3 and back.num_cells == m.num_cells
    assert np.array_equal(back.points, m.points)
    assert [(k, a.tolist()) for k, a in back.cells] == [(k, a.tolist()) for k, a in m.cells]
    assert np.array_equal(back.volumes, m.volumes)
    if extension != ".msh":  # tetia's .msh reader reads the mesh; fields there: `tetia remap --field`
        assert np.array_equal(np.ravel(back.cell_data["u"]), u)


def test_from_meshio_ignores_lower_dimensions_and_needs_corner_nodes(tmp_path):
    points = cube_points(40, 10)
    m = delaunay_mesh(points)
    tets = m.cells[0][1]
    boundary = np.array([[0, 1, 2], [4, 5, 6]])
    mesh = meshio.Mesh(points, [("vertex", [[0]]), ("triangle", boundary), ("tetra", tets), ("line", [[0, 1]])],
                       cell_data={"c": [np.zeros(1), np.ones(2), np.arange(len(tets)), np.zeros(1)]})
    t = tetia.Mesh.from_meshio(mesh)
    assert t.num_cells == len(tets) and t.ignored_cells == 4
    assert np.array_equal(t.cell_data["c"], np.arange(len(tets)))
    # second order: corners only when asked
    mids = np.arange(6 * len(tets)).reshape(-1, 6) % len(points)
    quadratic = meshio.Mesh(points, [("tetra10", np.hstack([tets, mids]))])
    with pytest.raises(ValueError, match="corner_nodes=True"):
        tetia.Mesh.from_meshio(quadratic)
    straight = tetia.Mesh.from_meshio(quadratic, corner_nodes=True)
    assert np.array_equal(straight.volumes, m.volumes)


def test_read_mesh_msh_by_tetias_reader_is_in_tag_order(tmp_path):
    points = square_points(60, 11)
    m = delaunay_mesh(points)
    path = str(tmp_path / "square.msh")
    meshio.write(path, m.to_meshio(), file_format="gmsh22", binary=False)
    back = tetia.read_mesh(path)
    assert back.dim == 2 and back.cells[0][0] == "triangle"
    assert np.array_equal(back.points, m.points)  # z = 0 in the file, dropped
    assert np.array_equal(back.volumes, m.volumes)


@pytest.mark.parametrize("file_format,binary", [("gmsh22", False), ("gmsh22", True), ("gmsh", False), ("gmsh", True)])
def test_read_mesh_msh_keeps_node_and_element_data(tmp_path, file_format, binary):
    points = cube_points(40, 12)
    m = delaunay_mesh(points)
    rng = np.random.default_rng(5)
    t = rng.standard_normal(m.num_points)
    v = rng.standard_normal((m.num_points, 3))
    rho = rng.standard_normal(m.num_cells)
    path = str(tmp_path / "cube.msh")
    meshio.write(path, m.to_meshio(point_data={"T": t, "v": v}, cell_data={"rho": rho}),
                 file_format=file_format, binary=binary)
    back = tetia.read_mesh(path)
    assert np.array_equal(back.points, m.points)
    assert np.array_equal(back.point_data["T"], t)
    assert back.point_data["v"].shape == (m.num_points, 3) and np.array_equal(back.point_data["v"], v)
    assert np.array_equal(back.cell_data["rho"], rho)
    # what meshio reads from the same file, and what a remap takes
    other = meshio.read(path)
    assert np.array_equal(np.ravel(other.point_data["T"]), back.point_data["T"])
    assert np.allclose(tetia.Remap(back, m, order=1)(back.point_data["T"]), t, rtol=0, atol=1e-12)


def test_read_mesh_msh_data_at_the_last_time_step(tmp_path):
    path = tmp_path / "steps.msh"
    block = "$ElementData\n1\n\"p\"\n1\n{time}\n3\n{step}\n1\n1\n1 {value}\n$EndElementData\n"
    path.write_text("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                    "$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n"
                    + block.format(time=0.0, step=0, value=1.5) + block.format(time=1.0, step=1, value=2.5)
                    + "$NodeData\n1\n\"q\"\n1\n0.0\n3\n0\n2\n4\n1 1 2\n2 3 4\n3 5 6\n4 7 8\n$EndNodeData\n"
                    + "$NodeData\n1\n\"r\"\n1\n0.0\n3\n0\n1\n4\n1 -1\n2 -2\n3 -3\n4 -4\n$EndNodeData\n")
    back = tetia.read_mesh(path)
    assert np.array_equal(back.cell_data["p"], [2.5])
    assert np.array_equal(back.point_data["q"], [[1, 2], [3, 4], [5, 6], [7, 8]])
    assert np.array_equal(back.point_data["r"], [-1, -2, -3, -4])
    # a field without a value for every node: left out with a warning naming it, the rest read
    # (r too, node data at the same step as q: the two are read together unless that fails)
    path.write_text(path.read_text().replace("4\n1 1 2\n", "3\n1 1 2\n").replace("4 7 8\n", ""))
    with pytest.warns(UserWarning, match='steps.msh: .*node.*; node data "q" left out'):
        back = tetia.read_mesh(path)
    assert "q" not in back.point_data and np.array_equal(back.cell_data["p"], [2.5])
    assert np.array_equal(back.point_data["r"], [-1, -2, -3, -4])


def test_read_mesh_msh_of_second_order_read_by_its_corners_keeps_its_fields(tmp_path):
    quadratic = tmp_path / "tetra10.msh"
    corners = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    mids = [(corners[a] + corners[b]) / 2 for a, b in ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3))]
    meshio.write(str(quadratic), meshio.Mesh(np.vstack([corners, mids]), [("tetra10", [list(range(10))])],
                                             point_data={"T": np.arange(10.0)}, cell_data={"rho": [np.array([7.0])]}),
                 file_format="gmsh22", binary=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        straight = tetia.read_mesh(quadratic, corner_nodes=True)
    assert np.array_equal(straight.point_data["T"], np.arange(10.0)) and np.array_equal(straight.cell_data["rho"], [7.0])


def test_file_errors_raise_os_error(tmp_path):
    with pytest.raises(FileNotFoundError):
        tetia.read_mesh(str(tmp_path / "missing.msh"))
    bad = tmp_path / "bad.msh"
    bad.write_text("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n")
    with pytest.raises(OSError, match=str(bad).replace(".", r"\.") + ".*line"):
        tetia.read_mesh(bad)
    garbage = tmp_path / "garbage.vtu"
    garbage.write_bytes(b"\x00\x01 not xml")
    with pytest.raises(OSError, match="garbage.vtu"):
        tetia.read_mesh(garbage)
    unknown = tmp_path / "mesh.unknown-format"
    unknown.write_text("1 2 3\n")
    with pytest.raises(OSError, match="unknown-format"):
        tetia.read_mesh(unknown)
    # a readable file whose mesh tetia cannot use: OSError naming the file and the cell
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    flat = tmp_path / "flat.vtu"
    meshio.write(str(flat), meshio.Mesh(points, [("tetra", [[0, 1, 2, 2]])]))
    with pytest.raises(OSError, match="flat.vtu: cell 0"):
        tetia.read_mesh(flat)
