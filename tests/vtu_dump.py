"""Reads a VTU file with VTK's own reader (Debian python3-vtk9) and prints it canonically, for
tests/test_io.cpp and tests/test_tri_mesh.cpp, which compare the text with what they wrote:

    points N
    x y z            (one line per point, repr of each double)
    cells M
    type n i0 i1 ... (one line per cell: VTK cell type, point count, point ids)
    point_array NAME TYPE v0 v1 ...   (every point data array, in file order; in NAME, % and
                                       space are written %25 and %20)
    cell_array NAME TYPE v0 v1 ...    (every cell data array)
    cell_array vtk:measure double ... (last: each cell's signed volume, area or length as VTK's
                                       vtkCellSizeFilter computes it from its node order)

Exit status 0, or 2 with a message when the file cannot be read.
"""
import sys

# The three modules it uses, not `import vtk` (every module: twice the start-up time, which the
# tests pay once per file they read).
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import VTK_DOUBLE, VTK_FLOAT
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader


def values(array):
    v = vtk_to_numpy(array).ravel()
    return " ".join(repr(float(x)) if array.GetDataType() in (VTK_FLOAT, VTK_DOUBLE) else str(int(x)) for x in v)


def main(path):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    if reader.GetErrorCode() != 0 or grid is None or grid.GetNumberOfCells() == 0:
        print(f"vtu_dump: {path}: VTK could not read it", file=sys.stderr)
        return 2
    out = [f"points {grid.GetNumberOfPoints()}"]
    for i in range(grid.GetNumberOfPoints()):
        out.append(" ".join(repr(float(c)) for c in grid.GetPoint(i)))
    out.append(f"cells {grid.GetNumberOfCells()}")
    for c in range(grid.GetNumberOfCells()):
        ids = grid.GetCell(c).GetPointIds()
        out.append(" ".join([str(grid.GetCellType(c)), str(ids.GetNumberOfIds())] +
                            [str(ids.GetId(k)) for k in range(ids.GetNumberOfIds())]))
    for kind, data in (("point_array", grid.GetPointData()), ("cell_array", grid.GetCellData())):
        for i in range(data.GetNumberOfArrays()):
            a = data.GetArray(i)
            name = a.GetName().replace("%", "%25").replace(" ", "%20")  # one token
            out.append(f"{kind} {name} {a.GetDataTypeAsString().replace(' ', '_')} {values(a)}")
    sizes = vtkCellSizeFilter()
    sizes.SetInputData(grid)
    sizes.Update()
    measured = sizes.GetOutput().GetCellData()
    measure = []
    for c in range(grid.GetNumberOfCells()):
        dim = grid.GetCell(c).GetCellDimension()
        name = {3: "Volume", 2: "Area", 1: "Length"}.get(dim)
        measure.append(repr(float(measured.GetArray(name).GetValue(c))) if name else "0.0")
    out.append("cell_array vtk:measure double " + " ".join(measure))
    print("\n".join(out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
