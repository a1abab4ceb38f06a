"""tetia.supermesh: the overlapping pairs of cells of two meshes, as NumPy arrays."""

from . import _tetia
from .mesh import as_mesh


class Supermesh:
    """The intersection of every source cell with every target cell it overlaps, per cell given
    (a hexahedron's tetrahedra count as the hexahedron), sorted by target cell:

      source_cell, target_cell  (p,) int64: the pair's cells (indices into the meshes' cells)
      volume                    (p,) float64: the measure of their intersection (area in 2D)
      centroid                  (p, 3) or (p, 2): its centroid
      intersection_volume       float: the total (compensated sum), what `tetia supermesh` prints
      candidates, pieces        pairs of simplices tested, and with an intersection
      seconds                   time spent building it
    """

    def __init__(self, source, target, arrays):
        self.source, self.target = source, target
        for key in ("source_cell", "target_cell", "volume", "centroid"):
            arrays[key].setflags(write=False)
        self.__dict__.update(arrays)

    @property
    def area(self):
        """The pair measures of a 2D supermesh (the same array as volume)."""
        return self.volume

    def __len__(self):
        return len(self.volume)

    def __repr__(self):
        return (f"<tetia.Supermesh: {len(self)} pairs, intersection volume {self.intersection_volume!r}, "
                f"{self.seconds:.3g} s>")


def supermesh(source, target, search="front", threads=None):
    """The supermesh of two meshes (tetia.Mesh or meshio.Mesh) of one dimension. search:
    "front" (advancing front, fastest on connected meshes) or "rtree"; threads: None for
    OpenMP's default, or a number >= 1. The GIL is released while it is built."""
    source, target = as_mesh(source, "source"), as_mesh(target, "target")
    return Supermesh(source, target, _tetia.supermesh(source._handle, target._handle, search, threads))
