/**
 * libFuzzer target: a rigid triangle surface read as Contact/Obstacle N/File reads it
 * (fem::read_triangle_surface: binary or ASCII STL, legacy VTK polydata or OBJ, told apart
 * by the content). The seeds are one small surface in each format.
 *
 * A malformed surface must end in warpchol::Error (InputError naming the file and line);
 * a surface that is read must hold a triangle, every corner an index of one of its points
 * and every point finite. Anything else (a crash, a sanitizer report, an exception of
 * another kind, a hang) is a finding.
 */

#include <warpchol/base/exceptions.h>
#include <warpchol/contact/triangle_surface.h>

#include "fuzz_input_file.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, const std::size_t size)
{
  static warpchol::fuzz::InputFile input(".surface");
  const std::string               &filename = input.write(data, size);
  try
    {
      const warpchol::fem::TriangleSurface surface = warpchol::fem::read_triangle_surface(filename);
      bool                                 valid   = !surface.triangles.empty();
      for (const auto &triangle : surface.triangles)
        for (const unsigned int corner : triangle)
          valid = valid && corner < surface.points.size();
      for (const auto &point : surface.points)
        valid = valid && point.allFinite();
      if (!valid)
        {
          std::fprintf(stderr, "read_triangle_surface accepted %zu triangles on %zu points, not all valid\n",
                       surface.triangles.size(), surface.points.size());
          std::abort();
        }
    }
  catch (const warpchol::Error &)
    {
      // Refused with a message: what a malformed surface should get.
    }
  return 0;
}
