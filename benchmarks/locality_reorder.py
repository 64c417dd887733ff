#!/usr/bin/env python3
"""Write a legacy VTK tetrahedral mesh renumbered for locality: the points in Morton
(Z-curve) order of their positions, the cells sorted by their smallest new point index.
An experiment for issue 26 (doc/targets/xeon/README.md): the element kernels read A and
the vertices in the order of the cells, so a mesh in its file's numbering (SOFA's) runs
them slower than the same mesh renumbered.

    python3 benchmarks/locality_reorder.py IN.vtk OUT.vtk
"""
import sys


def read_legacy_vtk(path):
    """The points and the tetrahedra of an ASCII legacy VTK unstructured grid."""
    lines = open(path).read().split('\n')
    first = next(k for k, line in enumerate(lines) if line.startswith('POINTS'))
    n_points = int(lines[first].split()[1])
    values, k = [], first + 1
    while len(values) < 3 * n_points:
        values += [float(x) for x in lines[k].split()]
        k += 1
    points = [values[3 * j:3 * j + 3] for j in range(n_points)]
    header = next(k for k, line in enumerate(lines) if line.startswith('CELLS'))
    n_cells = int(lines[header].split()[1])
    cells = [[int(x) for x in lines[header + 1 + e].split()[1:]] for e in range(n_cells)]
    return lines[:4], points, cells


def morton_code(point, lower, upper, bits=10):
    """The Z-curve index of a point of the box [lower, upper] on a 2^bits grid."""
    grid = [int((2**bits - 1) * (point[d] - lower[d]) / ((upper[d] - lower[d]) or 1)) for d in range(3)]
    code = 0
    for b in range(bits):
        for d in range(3):
            code |= ((grid[d] >> b) & 1) << (3 * b + d)
    return code


def main(source, target):
    header, points, cells = read_legacy_vtk(source)
    lower = [min(p[d] for p in points) for d in range(3)]
    upper = [max(p[d] for p in points) for d in range(3)]
    order = sorted(range(len(points)), key=lambda j: morton_code(points[j], lower, upper))
    new_index = {old: new for new, old in enumerate(order)}
    renumbered = sorted(([new_index[v] for v in cell] for cell in cells), key=lambda cell: (min(cell), sorted(cell)))
    lines = header + ['POINTS %d float' % len(points)] + ['%r %r %r' % tuple(points[j]) for j in order]
    lines += ['CELLS %d %d' % (len(cells), 5 * len(cells))] + ['4 ' + ' '.join(map(str, cell)) for cell in renumbered]
    lines += ['CELL_TYPES %d' % len(cells)] + ['10'] * len(cells) + ['']
    open(target, 'w').write('\n'.join(lines))


if __name__ == '__main__':
    if len(sys.argv) != 3:
        sys.exit('usage: locality_reorder.py IN.vtk OUT.vtk')
    main(sys.argv[1], sys.argv[2])
