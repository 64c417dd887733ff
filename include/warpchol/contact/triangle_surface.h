#pragma once

#include <warpchol/fem/small_dense.h>

#include <array>
#include <string>
#include <vector>

/**
 * @file
 * Rigid triangle surfaces (a table, ribs, a neighbouring organ) read from STL (ASCII or
 * binary), Wavefront OBJ or legacy VTK polydata files.
 */
namespace warpchol::fem
{
  /** Points and the triangles between them (indices into points). */
  struct TriangleSurface
  {
    std::vector<Vector3>                   points;
    std::vector<std::array<unsigned int, 3>> triangles;
  };

  /**
   * Read @p file_name, told apart by its content: binary STL (its size is 84 + 50 bytes per
   * triangle), ASCII STL ("solid"), legacy VTK ("# vtk DataFile", POLYDATA with POLYGONS
   * of three points; ASCII), else OBJ ("v x y z", "f a b c", polygons fanned into
   * triangles). Throws InputError "FILE:LINE: why" for a line that is not understood, a
   * coordinate that is not a finite number or an index out of range, "FILE: why" for a file
   * that cannot be read or holds no triangle, or one of zero area only.
   */
  TriangleSurface read_triangle_surface(const std::string &file_name);

} // namespace warpchol::fem
