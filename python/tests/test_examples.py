"""The scripts in examples/python/ run as a user would run them (their own checks included)."""

import os
import subprocess
import sys

from test_kernels import SOURCE


def run_example(name, *args, cwd):
    script = os.path.join(SOURCE, "examples", "python", name)
    result = subprocess.run([sys.executable, script, *args], cwd=cwd, capture_output=True, text=True, check=False)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout


def test_remap_meshio_writes_the_slice_and_the_target(tmp_path):
    out = run_example("remap_meshio.py", "-o", str(tmp_path / "slice.png"), cwd=tmp_path)
    assert (tmp_path / "slice.png").stat().st_size > 10000
    assert (tmp_path / "slice_target.vtu").exists()
    line = next(s for s in out.splitlines() if s.startswith("integral of f"))
    source, target = (float(w.rstrip(",")) for w in (line.split()[4], line.split()[6]))
    assert abs(source - target) < 1e-13  # conservation: both meshes fill the cube


def test_remap_meshio_on_files_with_a_field(tmp_path):
    import meshio
    import numpy as np

    from conftest import cube_points, delaunay_mesh

    a, b = delaunay_mesh(cube_points(200, 41)), delaunay_mesh(cube_points(100, 42))
    meshio.write(str(tmp_path / "a.vtu"), a.to_meshio(cell_data={"T": np.arange(a.num_cells, dtype=float)}))
    meshio.write(str(tmp_path / "b.vtk"), b.to_meshio())
    out = run_example("remap_meshio.py", "a.vtu", "b.vtk", "-o", "s.png", cwd=tmp_path)
    assert "integral of T" in out and (tmp_path / "s.png").exists()


def test_mortar_coupling_checks_pass(tmp_path):
    assert "mortar coupling: ok" in run_example("mortar_coupling.py", "--refine", "8", cwd=tmp_path)
