"""tetia: robust intersection of tetrahedra and triangles, supermeshes of non-matching meshes,
and conservative remap between them (P0, P1 and their lumped, bounded, discontinuous and
reconstructed variants), from NumPy arrays and meshio meshes.

    import tetia
    tetia.intersection_volume(U, V)          # U, V: (4, 3) or (n, 4, 3) arrays
    source = tetia.read_mesh("a.vtu")        # .msh by tetia's reader, other formats by meshio
    target = tetia.Mesh(points, {"tetra": cells})
    r = tetia.Remap(source, target, order=0) # built once
    u_target = r(u_source)                   # applied to many fields; r.matrix is SciPy CSR
    b = tetia.Remap(source, target, order=1, method="bounded")  # also "lumped", "discontinuous", "linear"
    u_target = tetia.remap_p1(source, target, u_source)  # P1 once, for large meshes: nothing kept

Every volume, area and remapped value is what the C++ library returns, bit for bit; the GIL is
released while tetia works, and every object is safe to use from several threads at once.
"""

from ._tetia import Polygon, Polyhedron, __version__, intersect, intersection_area, intersection_volume
from .mesh import Mesh, read_mesh
from .remap import Remap, remap_p1
from .supermesh import Supermesh, supermesh

__all__ = [
    "Mesh",
    "Polygon",
    "Polyhedron",
    "Remap",
    "Supermesh",
    "__version__",
    "intersect",
    "intersection_area",
    "intersection_volume",
    "read_mesh",
    "remap_p1",
    "supermesh",
]
