"""tetia.Mesh: a mesh from NumPy arrays, a file or a meshio mesh, and back to meshio.

A Mesh is immutable. Its cells are the cells given ("file cells"): tetrahedra, hexahedra, prisms
(meshio's "wedge") and pyramids in 3D, triangles and quadrilaterals in 2D (a plane: 2 coordinates,
or 3 with one z). tetia splits the others into simplices internally (conforming, no new nodes),
but every result is per cell given and in the order given: cell i is the i-th cell of the blocks,
block after block; nodes keep their order.
"""

import os

import numpy as np

from . import _tetia

# meshio's names of the cell types tetia reads, and Gmsh's numbers for them (mesh.hpp).
GMSH_TYPE = {"triangle": 2, "quad": 3, "tetra": 4, "hexahedron": 5, "wedge": 6, "pyramid": 7}
MESHIO_NAME = {t: name for name, t in GMSH_TYPE.items()}
NODES = {"triangle": 3, "quad": 4, "tetra": 4, "hexahedron": 8, "wedge": 6, "pyramid": 5}
DIMENSION = {"triangle": 2, "quad": 2, "tetra": 3, "hexahedron": 3, "wedge": 3, "pyramid": 3}
ALIASES = {"tetrahedron": "tetra", "quadrilateral": "quad", "prism": "wedge", "hexahedra": "hexahedron"}
# meshio's higher-order cells: their first nodes are the corners, in the same order.
HIGHER_ORDER = {
    "triangle6": "triangle", "triangle7": "triangle", "triangle10": "triangle",
    "quad8": "quad", "quad9": "quad",
    "tetra10": "tetra", "tetra20": "tetra",
    "hexahedron20": "hexahedron", "hexahedron24": "hexahedron", "hexahedron27": "hexahedron",
    "wedge12": "wedge", "wedge15": "wedge", "wedge18": "wedge",
    "pyramid13": "pyramid", "pyramid14": "pyramid",
}
# Cells of lower dimension that meshio meshes carry (boundaries, physical points): from_meshio
# ignores them, as tetia's .msh reader ignores a 3D mesh's boundary triangles.
LOWER_DIMENSION = {"vertex": 0, "line": 1, "line3": 1, "line4": 1}


def _canonical(name):
    name = str(name)
    return ALIASES.get(name, name)


def _blocks(cells, coordinate_dim):
    """The cells argument as [(meshio name, int array)], in order."""
    if isinstance(cells, dict):
        items = list(cells.items())
    elif isinstance(cells, (list, tuple)) and cells and (
            isinstance(cells[0], tuple) and len(cells[0]) == 2 and isinstance(cells[0][0], str)
            or hasattr(cells[0], "type") and hasattr(cells[0], "data")):
        items = [(c.type, c.data) if hasattr(c, "type") else c for c in cells]
    else:
        array = np.asarray(cells)
        if array.ndim != 2:
            raise ValueError(f"tetia: Mesh: cells must be an (m, k) array, a dict {{type: array}} or a list of "
                             f"(type, array), got an array of shape {array.shape}")
        bare = {3: "triangle", 8: "hexahedron", 6: "wedge", 5: "pyramid",
                4: "tetra" if coordinate_dim == 3 else "quad"}
        if array.shape[1] not in bare:
            raise ValueError(f"tetia: Mesh: cells of {array.shape[1]} nodes are of no type tetia reads "
                             f"(3 triangle, 4 tetra (or quad for 2D points), 5 pyramid, 6 wedge, 8 hexahedron)")
        items = [(bare[array.shape[1]], array)]
    blocks = []
    for name, data in items:
        kind = _canonical(name)
        if kind not in GMSH_TYPE:
            raise ValueError(f"tetia: Mesh: cell type {name!r} is not one tetia reads "
                             f"({', '.join(GMSH_TYPE)}; higher-order cells through Mesh.from_meshio(..., "
                             f"corner_nodes=True))")
        blocks.append((kind, data))
    if not blocks:
        raise ValueError("tetia: Mesh: no cells")
    return blocks


def _read_only(array):
    array.setflags(write=False)
    return array


class Mesh:
    """A mesh of tetrahedra (and hexahedra, prisms, pyramids) or of triangles (and
    quadrilaterals) in a plane.

    Mesh(points, cells, name="mesh"):
      points: (n, 3) coordinates, or (n, 2) for a 2D mesh (a 2D mesh may have 3 coordinates if
        the z of its cells' nodes is one value);
      cells: an (m, k) array of 0-based node indices (k = 4: tetrahedra, or quadrilaterals for 2D
        points; 3 triangles; 8 hexahedra; 6 wedges; 5 pyramids), a dict {meshio type: array} or
        a list of (meshio type, array) or of meshio CellBlocks. Node orders are meshio's (VTK's),
        which are Gmsh's for these types; either orientation is accepted (inverted cells are
        reoriented and counted in reoriented_cells).
    Raises ValueError, naming the cell or array, for anything tetia cannot use: indices out of
    range, cells without volume, non-finite coordinates, 2D cells off a plane, mixed dimensions.
    """

    def __init__(self, points, cells, name="mesh"):
        points = np.array(points, dtype=np.float64)  # a copy: the mesh stays as it was built
        if points.ndim != 2 or points.shape[1] not in (2, 3):
            raise ValueError(f"tetia: {name}: points must have shape (n, 3) or (n, 2), got {points.shape}")
        blocks = _blocks(cells, points.shape[1])
        kept = []
        for kind, data in blocks:
            array = np.asarray(data)
            if array.size == 0:
                array = array.reshape(0, NODES[kind])
            kept.append((kind, array))
        handle = _tetia.make_mesh(points, [(GMSH_TYPE[k], a) for k, a in kept], str(name))
        self._init(handle, points, [(k, np.array(a, dtype=np.int64)) for k, a in kept])

    def _init(self, handle, points, cells, point_data=None, cell_data=None, ignored_cells=0):
        self._handle = handle
        self.points = _read_only(points)
        self.cells = [(kind, _read_only(array)) for kind, array in cells]
        self.point_data = dict(point_data or {})
        self.cell_data = dict(cell_data or {})
        self.ignored_cells = ignored_cells

    @classmethod
    def _wrap(cls, handle, points, cells, **extra):
        mesh = cls.__new__(cls)
        mesh._init(handle, points, cells, **extra)
        return mesh

    # --- what it is --------------------------------------------------------------------------
    @property
    def dim(self):
        """3 (tetrahedra and other 3D cells) or 2 (triangles, quadrilaterals)."""
        return self._handle.dim

    @property
    def name(self):
        return self._handle.name

    @property
    def num_points(self):
        return self._handle.num_nodes

    @property
    def num_cells(self):
        """Cells as given (a hexahedron is one), the length of every per-cell array."""
        return self._handle.num_cells

    @property
    def volumes(self):
        """Each cell's volume (area in 2D), (num_cells,): the sum of its simplices'."""
        return self._handle.measures

    @property
    def cell_types(self):
        """Each cell's meshio type name, (num_cells,)."""
        return np.concatenate([np.full(len(a), k, dtype=object) for k, a in self.cells])

    @property
    def reoriented_cells(self):
        """Simplices given inverted (negative orientation) and turned around."""
        return self._handle.reoriented_cells

    @property
    def flat_cells(self):
        """Simplices without volume (kept: they intersect nothing)."""
        return self._handle.flat_cells

    @property
    def simplices(self):
        """The simplices tetia computes with, (s, 4) or (s, 3), positively oriented."""
        return self._handle.simplices

    @property
    def simplex_cell(self):
        """The cell each simplex belongs to, (s,)."""
        return self._handle.simplex_cell

    def __repr__(self):
        kinds = ", ".join(f"{len(a)} {k}" for k, a in self.cells)
        return f"<tetia.Mesh {self.name!r}: {self.dim}D, {self.num_points} points, {kinds}>"

    # --- meshio ------------------------------------------------------------------------------
    @classmethod
    def from_meshio(cls, mesh, corner_nodes=False, name="meshio mesh"):
        """A Mesh from a meshio.Mesh: its cells of the highest dimension among those tetia reads
        (lower-dimensional ones, such as boundary triangles or lines, are ignored and counted in
        ignored_cells), with its point_data and the cell_data of the kept blocks. Higher-order
        cells (tetra10, ...) need corner_nodes=True: they are then read by their corners
        (straight cells)."""
        blocks = []
        for block in mesh.cells:
            kind, data = block.type, np.asarray(block.data)
            if kind in HIGHER_ORDER:
                if not corner_nodes:
                    raise ValueError(f"tetia: {name}: {kind} cells are of order > 1: pass corner_nodes=True to "
                                     f"read them by their corners (straight cells)")
                kind, data = HIGHER_ORDER[kind], data[:, :NODES[HIGHER_ORDER[kind]]]
            blocks.append((kind, data))
        dims = [DIMENSION[k] if k in DIMENSION else LOWER_DIMENSION.get(k, -1) for k, _ in blocks]
        if not blocks or max(dims) < 2:
            raise ValueError(f"tetia: {name}: no cells tetia reads (triangles, quads, tetra, hexahedra, wedges, "
                             f"pyramids)")
        top = max(dims)
        unknown = [k for (k, _), d in zip(blocks, dims) if d < 0]
        if unknown:
            raise ValueError(f"tetia: {name}: cell type {unknown[0]!r} is not one tetia reads")
        keep = [i for i, d in enumerate(dims) if d == top]
        cells = [blocks[i] for i in keep]
        ignored = sum(len(blocks[i][1]) for i in range(len(blocks)) if dims[i] != top)
        result = cls(mesh.points, cells, name=name)
        result.point_data = dict(mesh.point_data)
        result.cell_data = {key: np.concatenate([np.asarray(values[i]) for i in keep])
                            for key, values in mesh.cell_data.items() if len(values) == len(blocks)}
        result.ignored_cells = ignored
        return result

    def to_meshio(self, point_data=None, cell_data=None):
        """A meshio.Mesh of the same points and cells (as given), with the mesh's point_data and
        cell_data and those given here (per point, and per cell as (num_cells, ...) arrays, which
        are split into meshio's blocks)."""
        import meshio

        points = {**self.point_data, **(point_data or {})}
        for key, values in points.items():
            if len(values) != self.num_points:
                raise ValueError(f"tetia: to_meshio: point_data[{key!r}] has {len(values)} rows, the mesh "
                                 f"{self.num_points} points")
        per_cell = {**self.cell_data, **(cell_data or {})}
        sizes = np.cumsum([len(a) for _, a in self.cells])[:-1]
        split = {}
        for key, values in per_cell.items():
            values = np.asarray(values)
            if len(values) != self.num_cells:
                raise ValueError(f"tetia: to_meshio: cell_data[{key!r}] has {len(values)} rows, the mesh "
                                 f"{self.num_cells} cells")
            split[key] = np.split(values, sizes)
        return meshio.Mesh(np.array(self.points), [(k, np.array(a)) for k, a in self.cells],
                           point_data=points, cell_data=split)


def read_mesh(path, corner_nodes=False):
    """A Mesh read from a file: Gmsh .msh (2.x, 4.1, ASCII or binary) with tetia's own strict
    reader (nodes in the order of their tags, cells in that of their element tags; boundary and
    other elements ignored), its node data and element data in point_data and cell_data ((n,)
    arrays for scalars, (n, components) otherwise; a field with several time steps at its last
    one; element-node data, and a field the mesh cannot take, such as data on boundary elements
    only, left out, the latter with a UserWarning); any other format meshio reads (VTU, XDMF,
    Exodus, MED, ...) through meshio and Mesh.from_meshio, with its point_data and cell_data.
    Raises OSError (FileNotFoundError if it does not exist) with a message naming the file, and
    the line, element or cell where there is one."""
    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(2, "tetia: no such file", path)
    if path.lower().endswith(".msh"):
        handle = _tetia.read_msh(path, corner_nodes)
        cells = [(MESHIO_NAME[t], a) for t, a in handle.file_cell_blocks()]
        point_data, cell_data = _tetia.read_msh_data(path, corner_nodes)
        return Mesh._wrap(handle, handle.nodes, cells, point_data=point_data, cell_data=cell_data)
    m = _meshio_read(path)
    try:
        return Mesh.from_meshio(m, corner_nodes=corner_nodes, name=path)
    except ValueError as error:
        raise OSError(str(error)) from error


def _meshio_read(path):
    """meshio.read, with every failure an OSError naming the file. (meshio 7.0's read() prints
    its readers' errors and calls sys.exit(1) when none of them can read a file: its readers are
    called here one by one instead, where meshio exposes them.)"""
    import pathlib

    import meshio

    helpers = getattr(meshio, "_helpers", None)
    readers = getattr(helpers, "reader_map", None)
    formats_of = getattr(helpers, "_filetypes_from_path", None)
    if readers is None or formats_of is None:
        try:
            return meshio.read(path)
        except (Exception, SystemExit) as error:  # noqa: B014 - see the docstring
            raise OSError(f"tetia: {path}: meshio cannot read it: {type(error).__name__}: {error}") from None
    try:
        formats = formats_of(pathlib.Path(path))
    except Exception as error:
        raise OSError(f"tetia: {path}: meshio knows no format of this name ({error})") from None
    reasons = []
    for name in formats:
        if name not in readers:
            reasons.append(f"{name}: no reader")
            continue
        try:
            return readers[name](path)
        except Exception as error:  # meshio's readers raise errors of many types
            reasons.append(f"as {name}: {type(error).__name__}: {error}")
    raise OSError(f"tetia: {path}: meshio cannot read it ({'; '.join(reasons) or 'no format'})")


def as_mesh(mesh, what):
    """A tetia.Mesh, or a meshio.Mesh converted to one (for the functions that take meshes)."""
    if isinstance(mesh, Mesh):
        return mesh
    if hasattr(mesh, "points") and hasattr(mesh, "cells") and hasattr(mesh, "cell_data"):
        return Mesh.from_meshio(mesh, name=what)
    raise TypeError(f"tetia: {what} must be a tetia.Mesh or a meshio.Mesh, not {type(mesh).__name__}")
