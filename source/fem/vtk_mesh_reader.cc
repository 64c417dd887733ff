/**
 * @file
 * read_vtk(): XML .vtu unstructured grids through the VTK library, kept in a translation
 * unit of its own so that VTK's headers stay out of everything else; legacy .vtk files go
 * to read_legacy_vtk() (legacy_vtk_reader.cc), our own parser.
 */

#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/input_file.h>
#include <warpchol/fem/mesh_readers.h>

#include <vtkCellType.h>
#include <vtkIdList.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkOutputWindow.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <sstream>

namespace warpchol::fem
{
  namespace
  {
    /**
     * Catches what VTK would print while a file is read (the reader's errors, but also
     * those of its XML parser and pipeline), and keeps the first message as one line
     * without VTK's "ERROR: In FILE, line N" header and object address. Installed as VTK's
     * output window for the duration of one read.
     */
    class CapturedMessages : public vtkOutputWindow
    {
    public:
      static CapturedMessages *New()
      {
        return new CapturedMessages;
      }

      void DisplayText(const char *text) override
      {
        if (!first.empty() || text == nullptr)
          return;
        std::istringstream lines(text);
        std::string        line;
        while (std::getline(lines, line))
          {
            if (line.empty() || line.rfind("ERROR: In ", 0) == 0 || line.rfind("Warning: In ", 0) == 0)
              continue;
            // "vtkXMLDataParser (0x55cc61c56a40): Error parsing XML ...": drop the address.
            const auto address = line.find("): ");
            if (address != std::string::npos && line.find(" (0x") < address)
              line = line.substr(address + 3);
            // VTK's messages may quote the file's bytes ("Unrecognized keyword: ...").
            first = excerpt(line, 160);
            return;
          }
      }

      std::string first;
    };

    /** Route VTK's messages to a CapturedMessages while it lives. */
    class MessageCapture
    {
    public:
      MessageCapture()
        : previous(vtkOutputWindow::GetInstance())
      {
        vtkOutputWindow::SetInstance(messages);
      }
      ~MessageCapture()
      {
        vtkOutputWindow::SetInstance(previous);
      }
      const std::string &first() const
      {
        return messages->first;
      }

    private:
      vtkSmartPointer<vtkOutputWindow> previous;
      vtkNew<CapturedMessages>         messages;
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
    check_input_file(filename, "mesh file");
    // By content first: SOFA's Bunny.vtk holds VTK XML.
    const MeshFormat format = detect_mesh_format(filename);
    const bool       xml    = format == MeshFormat::vtk_xml ||
                       (format == MeshFormat::unknown && filename.size() >= 4 &&
                        filename.compare(filename.size() - 4, 4, ".vtu") == 0);
    // Legacy files: our own parser (VTK's legacy reader crashed on malformed files).
    if (!xml)
      return read_legacy_vtk(filename);

    // VTK 9 also logs its errors on standard error through vtkLogger: the program reports
    // them itself, on one line. VTK serves no other purpose here, so its logging stays off.
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
    MessageCapture                     messages;
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(filename.c_str());
    reader->Update();
    vtkSmartPointer<vtkUnstructuredGrid> grid = reader->GetOutput();
    if (!messages.first().empty())
      throw InputError(filename + ": VTK cannot read it: " + messages.first());
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
        // VTK takes the cells as the file writes them: their point ids are not checked.
        if (points->GetNumberOfIds() != 4)
          throw InputError(location + " is a tetrahedron with " +
                           std::to_string(points->GetNumberOfIds()) + " points instead of 4");
        std::array<unsigned int, 4> tetrahedron;
        for (unsigned int a = 0; a < 4; ++a)
          {
            const vtkIdType id = points->GetId(a);
            if (id < 0 || id >= grid->GetNumberOfPoints())
              throw InputError(location + " refers to point " + std::to_string(id) +
                               ", which is not defined (the file has " +
                               std::to_string(grid->GetNumberOfPoints()) + " points)");
            tetrahedron[a] = static_cast<unsigned int>(id);
          }
        mesh.tetrahedra.push_back(tetrahedron);
        mesh.locations.push_back(location);
      }
    if (mesh.tetrahedra.empty())
      throw InputError(filename + ": the file holds no tetrahedron (VTK cell type 10)");
    return mesh;
  }
} // namespace warpchol::fem
