/**
 * @file
 * read_vtk(): legacy .vtk and XML .vtu unstructured grids through the VTK library, kept
 * in a translation unit of its own so that VTK's headers stay out of everything else.
 */

#include <warpchol/base/exceptions.h>
#include <warpchol/fem/mesh_readers.h>

#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkDataSetReader.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <fstream>

namespace warpchol::fem
{
  namespace
  {
    /** Collects the first error (or warning) a VTK reader reports instead of printing it. */
    class ReaderMessages : public vtkCommand
    {
    public:
      static ReaderMessages *New()
      {
        return new ReaderMessages;
      }

      void Execute(vtkObject *, unsigned long, void *call_data) override
      {
        if (first.empty() && call_data != nullptr)
          {
            first = static_cast<const char *>(call_data);
            // VTK's messages end with a newline and may span lines: keep the first one.
            const auto end = first.find_first_of("\r\n");
            if (end != std::string::npos)
              first.resize(end);
          }
      }

      std::string first;
    };

    /** VTK cell types of dimension < 3, skipped like Gmsh's lines and triangles. */
    bool is_lower_dimensional(const int type)
    {
      switch (type)
        {
          case VTK_VERTEX:
          case VTK_POLY_VERTEX:
          case VTK_LINE:
          case VTK_POLY_LINE:
          case VTK_TRIANGLE:
          case VTK_TRIANGLE_STRIP:
          case VTK_POLYGON:
          case VTK_PIXEL:
          case VTK_QUAD:
          case VTK_QUADRATIC_EDGE:
          case VTK_QUADRATIC_TRIANGLE:
          case VTK_QUADRATIC_QUAD:
            return true;
          default:
            return false;
        }
    }
  } // namespace

  TetrahedralMesh read_vtk(const std::string &filename)
  {
    if (!std::ifstream(filename))
      throw InputError(filename + ": cannot open the mesh file");
    const bool xml = filename.size() >= 4 && filename.compare(filename.size() - 4, 4, ".vtu") == 0;

    vtkNew<ReaderMessages>               messages;
    vtkSmartPointer<vtkUnstructuredGrid> grid;
    if (xml)
      {
        vtkNew<vtkXMLUnstructuredGridReader> reader;
        reader->AddObserver(vtkCommand::ErrorEvent, messages);
        reader->AddObserver(vtkCommand::WarningEvent, messages);
        reader->SetFileName(filename.c_str());
        reader->Update();
        grid = reader->GetOutput();
      }
    else
      {
        vtkNew<vtkUnstructuredGridReader> reader;
        reader->AddObserver(vtkCommand::ErrorEvent, messages);
        reader->AddObserver(vtkCommand::WarningEvent, messages);
        reader->SetFileName(filename.c_str());
        if (!reader->IsFileUnstructuredGrid())
          throw InputError(filename + ": not a legacy VTK file holding an UNSTRUCTURED_GRID" +
                           (messages->first.empty() ? std::string() : ": " + messages->first));
        reader->Update();
        grid = reader->GetOutput();
      }
    if (!messages->first.empty())
      throw InputError(filename + ": VTK cannot read it: " + messages->first);
    if (grid == nullptr || grid->GetNumberOfPoints() == 0)
      throw InputError(filename + ": VTK read no point from the file");

    TetrahedralMesh mesh;
    mesh.name = filename;
    mesh.vertices.resize(grid->GetNumberOfPoints());
    for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
      grid->GetPoint(p, mesh.vertices[p].data());

    vtkNew<vtkIdList> points;
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
      {
        const int type = grid->GetCellType(c);
        if (is_lower_dimensional(type))
          continue;
        const std::string location = filename + ": cell " + std::to_string(c);
        if (type != VTK_TETRA)
          throw InputError(location + " has VTK cell type " + std::to_string(type) +
                           ": the only volume cell supported is the linear tetrahedron (10)");
        grid->GetCellPoints(c, points);
        std::array<unsigned int, 4> tetrahedron;
        for (unsigned int a = 0; a < 4; ++a)
          tetrahedron[a] = static_cast<unsigned int>(points->GetId(a));
        mesh.tetrahedra.push_back(tetrahedron);
        mesh.locations.push_back(location);
      }
    if (mesh.tetrahedra.empty())
      throw InputError(filename + ": the file holds no tetrahedron (VTK cell type 10)");
    return mesh;
  }
} // namespace warpchol::fem
