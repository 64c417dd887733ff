/**
 * @file
 * read_vtk(): XML .vtu unstructured grids through the VTK library, kept in a translation
 * unit of its own so that VTK's headers stay out of everything else; legacy .vtk files go
 * to read_legacy_vtk() (legacy_vtk_reader.cc), our own parser.
 */

#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/input_file.h>
#include <warpchol/mesh/mesh_readers.h>

#include <vtkCellType.h>
#include <vtkIdList.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkOutputWindow.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <optional>
#include <regex>
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

    /**
     * The sizes an XML header announces, checked before VTK reads it: VTK allocates what
     * NumberOfPoints, NumberOfCells, NumberOfComponents and NumberOfTuples say, so that a
     * broken header ("NumberOfComponents="32147483647"") would make it reserve hundreds of
     * GB, or spin for minutes, for a file of a few hundred bytes. Each number must be an
     * integer, and the values an array announces must fit in the file: a value takes at
     * least one byte of raw data, and zlib, the one compressor that inflates more than
     * that, at most 1032:1. The file is read as a stream of tags, up to the appended data.
     */
    class HeaderSizeCheck
    {
    public:
      explicit HeaderSizeCheck(const std::string &filename)
        : filename(filename)
      {
        std::ifstream file = open_input_file(filename, "mesh file");
        file.seekg(0, std::ios::end);
        file_bytes = static_cast<double>(std::max<std::streamoff>(file.tellg(), 0));
        max_values = max_expansion * file_bytes;
        file.seekg(0);

        std::istreambuf_iterator<char> c(file), end;
        long                           line = 1;
        while (c != end)
          {
            if (*c == '\n')
              ++line;
            if (*c++ != '<')
              continue;
            const long  tag_line = line;
            std::string tag;
            for (; c != end && *c != '>' && tag.size() < max_tag_length; ++c)
              {
                if (*c == '\n')
                  ++line;
                tag += *c;
              }
            if (tag.rfind("AppendedData", 0) == 0)
              break;
            if (tag.rfind("Piece", 0) == 0)
              check_piece(tag, tag_line);
            else if (tag.rfind("DataArray", 0) == 0)
              check_array(tag, tag_line);
          }
      }

    private:
      /** zlib's largest ratio of inflated to deflated bytes. */
      static constexpr double      max_expansion  = 1032;
      static constexpr std::size_t max_tag_length = 1 << 16;

      /** The value of @p name in the tag's text, if it is there, as an integer. */
      std::optional<double> number(const std::string &tag, const std::string &name, const long line) const
      {
        const std::regex attribute("\\s" + name + "\\s*=\\s*(\"([^\"]*)\"|'([^']*)')");
        std::smatch      match;
        if (!std::regex_search(tag, match, attribute))
          return std::nullopt;
        const std::string value = match[2].matched ? match[2].str() : match[3].str();
        const auto        first = value.find_first_not_of(" \t\r\n");
        const auto        last  = value.find_last_not_of(" \t\r\n");
        const std::string digits =
          first == std::string::npos ? std::string() : value.substr(first, last - first + 1);
        if (digits.empty() || digits.size() > 18 ||
            digits.find_first_not_of("0123456789") != std::string::npos)
          throw InputError(at(line) + name + "=" + quote(value) + " is not a non-negative integer of at most 18 digits");
        return std::stod(digits);
      }

      void check_fits(const double values, const std::string &what, const long line) const
      {
        if (values > max_values)
          throw InputError(at(line) + "the header announces " + format_number(values, 15) + " " + what +
                           ", but a file of " + format_number(file_bytes, 15) + " bytes holds at most " +
                           format_number(max_values, 15) + " values (one byte each, inflated 1032:1)");
      }

      void check_piece(const std::string &tag, const long line)
      {
        piece_points = number(tag, "NumberOfPoints", line).value_or(0);
        piece_cells  = number(tag, "NumberOfCells", line).value_or(0);
        check_fits(3 * piece_points, "point coordinates", line);
        check_fits(piece_cells, "cells", line);
      }

      void check_array(const std::string &tag, const long line) const
      {
        const double components = number(tag, "NumberOfComponents", line).value_or(1);
        const double tuples =
          number(tag, "NumberOfTuples", line).value_or(std::max(piece_points, piece_cells));
        check_fits(components * tuples, "values in a DataArray", line);
      }

      std::string at(const long line) const
      {
        return filename + ":" + std::to_string(line) + ": ";
      }

      const std::string filename;
      double            max_values   = 0;
      double            file_bytes   = 0;
      double            piece_points = 0;
      double            piece_cells  = 0;
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
    const HeaderSizeCheck header_sizes(filename);
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
