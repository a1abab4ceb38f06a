"""Shared fixtures: unstructured meshes (Delaunay of random points, so that no test relies on a
structured grid), and the CLI (TETIA_CLI, set by ctest) for comparisons with the C++ tool."""

import os
import shutil
import subprocess

import numpy as np
import pytest
from scipy.spatial import Delaunay

import tetia


def cube_points(n, seed, lo=0.0, hi=1.0):
    """The 8 corners of [lo, hi]^3 and n random points inside: their Delaunay tetrahedra fill the
    cube exactly."""
    rng = np.random.default_rng(seed)
    corners = np.array([[i, j, k] for i in (lo, hi) for j in (lo, hi) for k in (lo, hi)], dtype=float)
    return np.vstack([corners, lo + (hi - lo) * rng.random((n, 3))])


def square_points(n, seed, lo=0.0, hi=1.0):
    rng = np.random.default_rng(seed)
    corners = np.array([[i, j] for i in (lo, hi) for j in (lo, hi)], dtype=float)
    return np.vstack([corners, lo + (hi - lo) * rng.random((n, 2))])


def delaunay_mesh(points, name="delaunay"):
    return tetia.Mesh(points, Delaunay(points).simplices, name=name)


@pytest.fixture(scope="session")
def cubes():
    """Two non-matching unstructured tetrahedral meshes of the unit cube."""
    return delaunay_mesh(cube_points(300, 1), "source"), delaunay_mesh(cube_points(200, 2), "target")


@pytest.fixture(scope="session")
def squares():
    """Two non-matching unstructured triangular meshes of the unit square."""
    return delaunay_mesh(square_points(300, 3), "source"), delaunay_mesh(square_points(200, 4), "target")


@pytest.fixture(scope="session")
def cli():
    """The tetia executable (ctest gives its path; else one on PATH), or skip."""
    path = os.environ.get("TETIA_CLI") or shutil.which("tetia")
    if not path:
        pytest.skip("the tetia executable is not known (TETIA_CLI)")
    return path


def run_cli(cli, *args, stdin=None):
    result = subprocess.run([cli, *args], input=stdin, capture_output=True, text=True, check=False)
    assert result.returncode == 0, result.stderr
    return result.stdout
