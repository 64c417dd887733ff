/**
 * libFuzzer target: a mesh file read as the programs read it (fem::read_mesh: the reader
 * that the extension selects, the element checks, deal.II's GridIn). Built three times,
 * with WARPCHOL_FUZZ_MESH_EXTENSION ".msh" (fuzz_gmsh), ".vtk" (fuzz_vtk, legacy VTK) and
 * ".vtu" (fuzz_vtu, VTK XML), so that each reader has its own corpus.
 *
 * A malformed mesh must end in warpchol::Error (InputError naming the file, line or cell);
 * a mesh that is read must give a triangulation with a cell. Anything else (a crash, a
 * sanitizer report, an exception of another kind, a hang) is a finding.
 */

#include <warpchol/base/exceptions.h>
#include <warpchol/mesh/mesh_readers.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/grid/tria.h>

#include "fuzz_input_file.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>

/**
 * deal.II's exceptions (GridIn's) collect the symbols of their stack when their message is
 * read, a large part of the time of an input that fails; the program cuts the stack off
 * their messages anyway.
 */
extern "C" int LLVMFuzzerInitialize(int *, char ***)
{
  dealii::deal_II_exceptions::suppress_stacktrace_in_exceptions();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, const std::size_t size)
{
  static warpchol::fuzz::InputFile input(WARPCHOL_FUZZ_MESH_EXTENSION);
  const std::string               &filename = input.write(data, size);
  try
    {
      dealii::Triangulation<3> triangulation;
      const auto               numbering = warpchol::fem::read_mesh(filename, triangulation);
      long                     n_used    = 0;
      for (const long v : numbering.vertex_of_file_vertex)
        n_used += v >= 0;
      if (triangulation.n_active_cells() == 0 || triangulation.n_vertices() != n_used)
        {
          std::fprintf(stderr, "read_mesh accepted a mesh with %u cells and %u vertices (%ld used)\n",
                       triangulation.n_active_cells(), triangulation.n_vertices(), n_used);
          std::abort();
        }
    }
  catch (const warpchol::Error &)
    {
      // Refused with a message: what a malformed mesh should get.
    }
  return 0;
}
