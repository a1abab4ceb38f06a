"""tetia.Remap: a conservative remap between two meshes, built once and applied to many fields."""

import functools

import numpy as np

from . import _tetia
from .mesh import as_mesh


def _csr(triple):
    import scipy.sparse

    data, indices, indptr, shape = triple
    return scipy.sparse.csr_matrix((data, indices, indptr), shape=shape)


class Remap:
    """Remap(source, target, order=0, method="standard", normalization="cell_volume", search="front",
    threads=None)

    order 0 (P0): cell averages in and out, one value per cell given (a hexahedron is one cell).
      u_T = sum_S |S cap T| u_S / d_T, with d_T the target cell's volume (normalization
      "cell_volume": the field counts as 0 outside the source) or its covered volume
      ("covered_volume": 0 where nothing covers it). Conservative: the integrals over the
      overlap agree.
    order 1 (P1): nodal values in and out, the Galerkin (L2) projection M_t u_t = M_ts u_s
      (conjugate gradients on the consistent mass matrix M_t).

    method (tetia/remap_methods.hpp says what each computes; all conserve the integral over the
    overlap):
      "standard"       P0 (order 0) or Galerkin P1 (order 1), as above
      "lumped"         order 1: the lumped-mass projection (first order, bounded)
      "bounded"        order 1: Galerkin corrected by clip-and-assured-sum, within the local
                       bounds of the source exactly
      "discontinuous"  order 1: the L2 projection onto discontinuous P1 on the target, one value
                       per target simplex and vertex (rows = simplices x (d + 1), in the order of
                       the simplices' nodes: mesh.simplices); order 0: cell averages of a
                       discontinuous source (cols = source simplices x (d + 1))
      "linear"         order 0: second-order cell averages (limited least-squares gradients)
    normalization ("cell_volume" or "covered_volume") applies to order 0 and to "lumped".

    r(u) remaps u of shape (cols,) or (cols, k) (k components, each on its own) to (rows,) or
    (rows, k): bit for bit what tetia::Remap::apply returns. Safe to call from several threads
    at once (the GIL is released while it runs).
    r.matrix       the operator of order 0 as a scipy.sparse.csr_matrix (r.matrix @ u == r(u) to
                   rounding); order 1 raises ValueError (M_t^-1 M_ts is dense: use r(u), or
                   mixed_mass and target_mass)
    r.mixed_mass   M (rows target, columns source): the pair volumes |S cap T| (order 0) or the
                   mixed mass matrix M_ts (order 1), CSR
    r.target_mass  diag(d_T) (order 0) or the target's consistent mass matrix M_t (order 1), CSR
    r.coverage     per target cell, the fraction of its volume the source covers, (cells,)
    r.node_coverage  per target node, the fraction of its basis function's integral the source
                   covers (order 1 with nodal results; else ValueError)
    For "lumped" and "discontinuous" r.matrix is the operator: r(u) is r.matrix @ u summed row by
    row in the entries' order, what `tetia remap --save-operator` writes; "bounded" and "linear"
    have none (their limiters depend on the field: ValueError).
    """

    def __init__(self, source, target, order=0, method="standard", normalization="cell_volume", search="front",
                 threads=None):
        self.source, self.target = as_mesh(source, "source"), as_mesh(target, "target")
        if not isinstance(order, (int, np.integer)) or isinstance(order, bool):
            raise ValueError(f"tetia: Remap: order must be 0 or 1, not {order!r}")
        if not isinstance(method, str):
            raise ValueError(f"tetia: Remap: method must be a string, not {method!r}")
        self.method = method
        self._handle = _tetia.RemapHandle(self.source._handle, self.target._handle, int(order), method,
                                          normalization, search, threads)

    @property
    def order(self):
        return self._handle.order

    @property
    def shape(self):
        """(rows, cols): values per component of a result (target cells or nodes) and of a field
        (source cells or nodes)."""
        return (self._handle.rows, self._handle.cols)

    @property
    def intersection_volume(self):
        """The volume (area) of the overlap of the two meshes, as tetia.supermesh gives it."""
        return self._handle.intersection_volume

    def __call__(self, field):
        return self._handle.apply(field, False)

    def apply(self, field, report=False):
        """r(field); with report=True, (result, {"iterations", "residual"}) of the last
        component's conjugate gradient solve (order 1; zeros for order 0)."""
        return self._handle.apply(field, bool(report))

    @functools.cached_property
    def matrix(self):
        return _csr(self._handle.matrix())

    @functools.cached_property
    def mixed_mass(self):
        return _csr(self._handle.mixed_mass())

    @functools.cached_property
    def target_mass(self):
        return _csr(self._handle.target_mass())

    @functools.cached_property
    def coverage(self):
        c = self._handle.coverage()
        c.setflags(write=False)
        return c

    @functools.cached_property
    def node_coverage(self):
        c = self._handle.node_coverage()
        c.setflags(write=False)
        return c

    def __repr__(self):
        return (f"<tetia.Remap order {self.order}, {self.method}: {self.shape[1]} -> {self.shape[0]} values per "
                "component>")


def remap_p1(source, target, field, search="front", threads=None, report=False):
    """P1 remap of nodal values straight from two meshes, for large meshes: the supermesh is
    handed to the loads as its pieces are found and never kept (tetia::P1Loads), so memory is
    about 100 B per piece instead of the 370 B that Remap(order=1) needs. field: (n,) or (n, k),
    one row per source node; returns (m,) or (m, k), one row per target node: bit for bit
    Remap(source, target, order=1)(field). With report=True, (result, {"iterations",
    "residual"}) of the last component's solve. Build a Remap instead to apply one operator to
    many fields, or to get its matrices.
    """
    source, target = as_mesh(source, "source"), as_mesh(target, "target")
    return _tetia.remap_p1(source._handle, target._handle, field, search, threads, bool(report))
