"""tetia.intersection_volume / intersection_area / intersect: the C++ kernels' numbers, bit for
bit (through the CLI, which prints 17 digits), batches equal to single calls, and bad input."""

import os

import numpy as np
import pytest

import tetia
from conftest import run_cli

SOURCE = os.environ.get("TETIA_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
REFERENCE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)


def pairs_of(path, numbers):
    rows = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if line and not line.startswith("#"):
                rows.append([float(x) for x in line.split()])
    a = np.array(rows)
    assert a.shape[1] == numbers
    return a


def random_tets(n, seed, scale=1.0):
    rng = np.random.default_rng(seed)
    return scale * rng.standard_normal((n, 4, 3))


def test_volumes_bit_for_bit_as_the_cli(cli):
    pairs = pairs_of(os.path.join(SOURCE, "examples", "pairs.txt"), 24)
    rng = np.random.default_rng(7)
    # the examples, random pairs, and adversarial ones: scales, a sliver, a shared face nudged
    extra = [np.concatenate([random_tets(1, s).ravel(), random_tets(1, s + 100).ravel()]) for s in range(40)]
    extra += [np.concatenate([REFERENCE.ravel() * 1e-200, (REFERENCE * 0.5e-200 + 1e-201).ravel()])]
    extra += [np.concatenate([REFERENCE.ravel() * 1e150, (REFERENCE[[1, 0, 2, 3]] * 1e150).ravel()])]
    sliver = REFERENCE.copy()
    sliver[3] = [0.3, 0.3, 1e-12]
    extra += [np.concatenate([REFERENCE.ravel(), sliver.ravel()])]
    extra += [np.concatenate([REFERENCE.ravel(), (REFERENCE + rng.uniform(-1e-15, 1e-15, (4, 3))).ravel()])]
    pairs = np.vstack([pairs, np.array(extra)])
    text = "\n".join(" ".join(repr(float(x)) for x in row) for row in pairs) + "\n"
    expected = np.array([float(v) for v in run_cli(cli, "pairs", stdin=text).split()])
    U, V = pairs[:, :12].reshape(-1, 4, 3), pairs[:, 12:].reshape(-1, 4, 3)
    got = tetia.intersection_volume(U, V)
    assert got.dtype == np.float64 and got.shape == (len(pairs),)
    assert np.array_equal(got, expected)  # bit for bit
    for i in range(len(pairs)):
        assert tetia.intersection_volume(U[i], V[i]) == expected[i]
        assert tetia.intersect(U[i], V[i]).volume == expected[i]


def test_areas_bit_for_bit_as_the_cli(cli):
    pairs = pairs_of(os.path.join(SOURCE, "examples", "triangle_pairs.txt"), 12)
    rng = np.random.default_rng(8)
    pairs = np.vstack([pairs, rng.standard_normal((50, 12))])
    text = "\n".join(" ".join(repr(float(x)) for x in row) for row in pairs) + "\n"
    expected = np.array([float(v) for v in run_cli(cli, "pairs", "--dim", "2", stdin=text).split()])
    A, B = pairs[:, :6].reshape(-1, 3, 2), pairs[:, 6:].reshape(-1, 3, 2)
    assert np.array_equal(tetia.intersection_area(A, B), expected)
    for i in range(len(pairs)):
        assert tetia.intersection_area(A[i], B[i]) == expected[i]
        assert tetia.intersect(A[i], B[i]).area == expected[i]


def test_symmetry_and_vertex_permutation():
    U, V = random_tets(200, 1), random_tets(200, 2)
    uv = tetia.intersection_volume(U, V)
    scale = np.maximum(np.abs(np.linalg.det(U[:, 1:] - U[:, :1])), np.abs(np.linalg.det(V[:, 1:] - V[:, :1])))
    assert np.all(np.abs(tetia.intersection_volume(V, U) - uv) <= 1e-13 * scale)
    assert np.all(np.abs(tetia.intersection_volume(U[:, [2, 0, 3, 1]], V[:, [1, 3, 0, 2]]) - uv) <= 1e-13 * scale)


def test_polyhedron_is_consistent():
    U = REFERENCE
    V = 0.8 * REFERENCE[[0, 2, 1, 3]] + np.array([0.1, 0.15, 0.05])
    p = tetia.intersect(U, V)
    k = len(p)
    assert not p.empty and k == p.points.shape[0] and p.points.shape == (k, 3)
    assert p.bary.shape == (k, 4) and p.labels.shape == (k, 3) and p.labels.dtype == np.uint8
    assert np.all(p.labels < 8) and np.all(np.diff(p.labels.astype(int), axis=1) > 0)
    # barycentric coordinates in V reproduce the points; they sum to one
    assert np.allclose(p.bary.sum(axis=1), 1.0)
    assert np.allclose(p.bary @ V, p.points)
    # every corner is on three facets, the facets' labels are the corners' labels
    assert sum(len(f) for f in p.facets) == 3 * k
    for f, label in zip(p.facets, p.facet_labels):
        assert all(label in p.labels[c] for c in f)
    tets = p.tetrahedra()
    vols = np.linalg.det(tets[:, 1:] - tets[:, :1]) / 6
    assert np.all(vols >= 0) and abs(vols.sum() - p.volume) <= 1e-15
    assert np.allclose(p.centroid, np.einsum("t,tc->c", vols, tets.mean(axis=1)) / vols.sum())


def test_disjoint_and_touching_are_empty():
    assert tetia.intersection_volume(REFERENCE, REFERENCE + 2.0) == 0.0
    p = tetia.intersect(REFERENCE, REFERENCE + 2.0)
    assert p.empty and p.volume == 0.0 and p.points.shape == (0, 3) and p.tetrahedra().shape == (0, 4, 3)
    reflected = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], dtype=float)
    assert tetia.intersection_volume(REFERENCE, reflected) == 0.0


def test_inputs_of_other_types_and_layouts():
    V = REFERENCE * 0.5 + 0.125  # exact in float32
    expected = tetia.intersection_volume(REFERENCE, V)
    assert tetia.intersection_volume(REFERENCE.tolist(), V.tolist()) == expected
    assert tetia.intersection_volume(np.asfortranarray(REFERENCE), V.astype(np.float32)) == expected
    assert tetia.intersection_volume(REFERENCE.astype(int), V) == expected
    batch = np.stack([REFERENCE, V, REFERENCE])[:, :, ::-1][:, :, ::-1]  # a non-contiguous view
    assert np.array_equal(tetia.intersection_volume(batch[::2], batch[::2]), [1 / 6, 1 / 6])
    assert tetia.intersection_volume(np.zeros((0, 4, 3)), np.zeros((0, 4, 3))).shape == (0,)


@pytest.mark.parametrize("U, V, message", [
    (np.zeros((3, 3)), REFERENCE, "U: expected shape (4, 3) or (n, 4, 3), got (3, 3)"),
    (REFERENCE, np.zeros((2, 4, 3)), "U and V must have the same shape"),
    (np.where(np.eye(4, 3) > 0, np.nan, 0.0), REFERENCE, "U[0, 0] is not finite (nan)"),
    (REFERENCE, np.full((4, 3), np.inf), "V[0, 0] is not finite (inf)"),
    (np.array([["a"] * 3] * 4), REFERENCE, "U: expected real numbers"),
    (REFERENCE + 0j, REFERENCE, "U: expected real numbers"),
])
def test_bad_input_raises_value_error(U, V, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")
                       .replace("]", r"\]")):
        tetia.intersection_volume(U, V)


def test_bad_triangles_raise_value_error():
    with pytest.raises(ValueError, match=r"A: expected shape \(3, 2\)"):
        tetia.intersection_area(np.zeros((3, 3)), np.zeros((3, 3)))
    with pytest.raises(ValueError, match="not finite"):
        tetia.intersect(np.array([[0, 0], [1, 0], [0, np.nan]]), np.eye(3, 2))
