#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/input_file.h>
#include <warpchol/mesh/mesh_readers.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/grid/grid_in.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <unordered_map>

namespace warpchol::fem
{
  namespace
  {
    /** Reads a text file line by line and names "FILE:LINE" in its errors. */
    class LineReader
    {
    public:
      explicit LineReader(const std::string &filename)
        : filename(filename)
        , input(open_input_file(filename, "mesh file"))
      {}

      /** The next non-blank line, split into words; throws at the end of the file. */
      const std::vector<std::string> &next(const std::string &expected)
      {
        std::string line;
        while (std::getline(input, line))
          {
            ++line_number;
            split(line);
            if (!words.empty())
              return words;
          }
        // What is expected may come from the file (the end of a section it opened).
        throw InputError(filename + ":" + std::to_string(line_number) +
                         ": unexpected end of file, expected " + excerpt(expected, 80));
      }

      /** The next line must be the single word @p keyword. */
      void expect(const std::string &keyword)
      {
        const auto &line = next(keyword);
        if (line.size() != 1 || line[0] != keyword)
          fail("expected " + keyword + ", found " + joined());
      }

      /** Skip lines up to and including the single word @p keyword. */
      void skip_to(const std::string &keyword)
      {
        while (true)
          {
            const auto &line = next(keyword);
            if (line.size() == 1 && line[0] == keyword)
              return;
          }
      }

      [[noreturn]] void fail(const std::string &message) const
      {
        throw InputError(location() + ": " + message);
      }

      std::string location() const
      {
        return filename + ":" + std::to_string(line_number);
      }

      long integer(const std::string &word, const std::string &what) const
      {
        std::size_t used  = 0;
        long        value = 0;
        try
          {
            value = std::stol(word, &used);
          }
        catch (...)
          {
            used = 0;
          }
        if (used != word.size())
          fail(what + " " + quote(word) + " is not an integer");
        return value;
      }

      double real(const std::string &word, const std::string &what) const
      {
        std::size_t used  = 0;
        double      value = 0;
        try
          {
            value = std::stod(word, &used);
          }
        catch (...)
          {
            used = 0;
          }
        if (used != word.size() || !std::isfinite(value))
          fail(what + " " + quote(word) + " is not a finite number");
        return value;
      }

      /** A count on a line of its own (or the first word of the line). */
      long count(const std::string &what)
      {
        const auto &line  = next(what);
        const long  value = integer(line[0], what);
        if (value < 0)
          fail(what + " must not be negative, got " + std::to_string(value));
        return value;
      }

      /** The words of the current line, quoted for a message (quote()). */
      std::string joined() const
      {
        std::string text;
        for (const auto &word : words)
          text += (text.empty() ? "" : " ") + word;
        return quote(text, 60);
      }

      const std::string filename;

    private:
      void split(const std::string &line)
      {
        words.clear();
        std::istringstream stream(line);
        std::string        word;
        while (stream >> word)
          words.push_back(word);
      }

      std::ifstream            input;
      std::vector<std::string> words;
      long                     line_number = 0;
    };

    /** Gmsh element types of dimension < 3 (points, lines, triangles, quadrangles). */
    bool is_lower_dimensional(const long type)
    {
      static const long types[] = {1, 2, 3, 8, 9, 10, 15, 16, 20, 21, 22, 23, 24, 25, 26, 27, 28};
      return std::find(std::begin(types), std::end(types), type) != std::end(types);
    }

    constexpr long gmsh_tetrahedron = 4;

    /** Collects nodes by their Gmsh tag and tetrahedra referring to them. */
    class GmshMeshBuilder
    {
    public:
      explicit GmshMeshBuilder(LineReader &reader)
        : reader(reader)
      {
        mesh.name = reader.filename;
      }

      void add_node(const long tag, const std::array<double, 3> &position)
      {
        if (!index_of_tag.emplace(tag, mesh.vertices.size()).second)
          reader.fail("node " + std::to_string(tag) + " is defined twice");
        mesh.vertices.push_back(position);
      }

      /** An element of Gmsh type @p type with the node tags @p nodes. */
      void add_element(const long number, const long type, const std::vector<long> &nodes)
      {
        if (is_lower_dimensional(type))
          return;
        if (type != gmsh_tetrahedron)
          reader.fail("element " + std::to_string(number) + " has Gmsh type " +
                      std::to_string(type) + ": the only volume element supported is the "
                      "linear tetrahedron (type 4)");
        if (nodes.size() != 4)
          reader.fail("tetrahedron " + std::to_string(number) + " has " +
                      std::to_string(nodes.size()) + " nodes instead of 4");
        std::array<unsigned int, 4> tetrahedron;
        for (unsigned int a = 0; a < 4; ++a)
          {
            const auto found = index_of_tag.find(nodes[a]);
            if (found == index_of_tag.end())
              reader.fail("element " + std::to_string(number) + " refers to node " +
                          std::to_string(nodes[a]) + ", which is not defined");
            tetrahedron[a] = found->second;
          }
        mesh.tetrahedra.push_back(tetrahedron);
        mesh.locations.push_back(reader.location() + ": element " + std::to_string(number));
      }

      TetrahedralMesh finish()
      {
        if (mesh.tetrahedra.empty())
          throw InputError(reader.filename + ": the file holds no tetrahedron (Gmsh element "
                                             "type 4)");
        return std::move(mesh);
      }

    private:
      LineReader                           &reader;
      TetrahedralMesh                       mesh;
      std::unordered_map<long, unsigned int> index_of_tag;
    };

    std::array<double, 3> read_point(const LineReader &reader, const std::vector<std::string> &line,
                                     const std::size_t first)
    {
      return {{reader.real(line[first], "coordinate"), reader.real(line[first + 1], "coordinate"),
               reader.real(line[first + 2], "coordinate")}};
    }

    /** $NOD/$Nodes of versions 1 and 2: "count", then "tag x y z" lines, then the end tag. */
    void read_nodes_v1_v2(LineReader &reader, GmshMeshBuilder &builder, const std::string &end)
    {
      const long n_nodes = reader.count("the number of nodes");
      for (long i = 0; i < n_nodes; ++i)
        {
          const auto &line = reader.next("a node line 'tag x y z'");
          if (line.size() != 4)
            reader.fail("a node line must read 'tag x y z', found " + reader.joined());
          builder.add_node(reader.integer(line[0], "node tag"), read_point(reader, line, 1));
        }
      reader.expect(end);
    }

    /** $ELM of version 1: "number type physical elementary n_nodes node...". */
    void read_elements_v1(LineReader &reader, GmshMeshBuilder &builder)
    {
      const long n_elements = reader.count("the number of elements");
      for (long i = 0; i < n_elements; ++i)
        {
          const auto &line = reader.next("an element line");
          if (line.size() < 5)
            reader.fail("an element line must read 'number type physical elementary n_nodes "
                        "nodes...', found " + reader.joined());
          const long n_nodes = reader.integer(line[4], "node count");
          if (n_nodes < 1 || static_cast<std::size_t>(n_nodes) + 5 != line.size())
            reader.fail("element " + excerpt(line[0]) + " announces " + std::to_string(n_nodes) + " nodes but lists " +
                        std::to_string(line.size() - 5));
          std::vector<long> nodes;
          for (std::size_t k = 5; k < line.size(); ++k)
            nodes.push_back(reader.integer(line[k], "node tag"));
          builder.add_element(reader.integer(line[0], "element number"),
                              reader.integer(line[1], "element type"), nodes);
        }
      reader.expect("$ENDELM");
    }

    /** $Elements of version 2: "number type n_tags tag... node...". */
    void read_elements_v2(LineReader &reader, GmshMeshBuilder &builder)
    {
      const long n_elements = reader.count("the number of elements");
      for (long i = 0; i < n_elements; ++i)
        {
          const auto &line = reader.next("an element line");
          if (line.size() < 4)
            reader.fail("an element line must read 'number type n_tags tags... nodes...', "
                        "found " + reader.joined());
          const long n_tags = reader.integer(line[2], "tag count");
          if (n_tags < 0 || static_cast<std::size_t>(n_tags) + 3 >= line.size())
            reader.fail("element " + excerpt(line[0]) + " has no node after its " + std::to_string(n_tags) + " tags");
          std::vector<long> nodes;
          for (std::size_t k = 3 + n_tags; k < line.size(); ++k)
            nodes.push_back(reader.integer(line[k], "node tag"));
          builder.add_element(reader.integer(line[0], "element number"),
                              reader.integer(line[1], "element type"), nodes);
        }
      reader.expect("$EndElements");
    }

    /** $Nodes of version 4.1: entity blocks of tags, then coordinates. */
    void read_nodes_v4(LineReader &reader, GmshMeshBuilder &builder)
    {
      const auto &header = reader.next("'numEntityBlocks numNodes minNodeTag maxNodeTag'");
      if (header.size() != 4)
        reader.fail("expected 'numEntityBlocks numNodes minNodeTag maxNodeTag'");
      const long n_blocks = reader.integer(header[0], "block count");
      for (long block = 0; block < n_blocks; ++block)
        {
          const auto &block_header = reader.next("a node block header");
          if (block_header.size() != 4)
            reader.fail("expected 'entityDim entityTag parametric numNodesInBlock'");
          const long entity_dimension = reader.integer(block_header[0], "entity dimension");
          // The dimension sets the number of words of each coordinate line below.
          if (entity_dimension < 0 || entity_dimension > 3)
            reader.fail("entity dimension " + block_header[0] + " is not 0, 1, 2 or 3");
          const long parametric       = reader.integer(block_header[2], "parametric flag");
          const long n_nodes          = reader.integer(block_header[3], "node count");
          std::vector<long> tags;
          for (long i = 0; i < n_nodes; ++i)
            tags.push_back(reader.integer(reader.next("a node tag")[0], "node tag"));
          const std::size_t words = 3 + (parametric != 0 ? entity_dimension : 0);
          for (long i = 0; i < n_nodes; ++i)
            {
              const auto &line = reader.next("node coordinates");
              if (line.size() != words)
                reader.fail("expected " + std::to_string(words) + " numbers for node " +
                            std::to_string(tags[i]) + ", found " + reader.joined());
              builder.add_node(tags[i], read_point(reader, line, 0));
            }
        }
      reader.expect("$EndNodes");
    }

    /** $Elements of version 4.1: entity blocks of "tag node..." lines of one type. */
    void read_elements_v4(LineReader &reader, GmshMeshBuilder &builder)
    {
      const auto &header = reader.next("'numEntityBlocks numElements minTag maxTag'");
      if (header.size() != 4)
        reader.fail("expected 'numEntityBlocks numElements minElementTag maxElementTag'");
      const long n_blocks = reader.integer(header[0], "block count");
      for (long block = 0; block < n_blocks; ++block)
        {
          const auto &block_header = reader.next("an element block header");
          if (block_header.size() != 4)
            reader.fail("expected 'entityDim entityTag elementType numElementsInBlock'");
          const long type       = reader.integer(block_header[2], "element type");
          const long n_elements = reader.integer(block_header[3], "element count");
          for (long i = 0; i < n_elements; ++i)
            {
              const auto &line = reader.next("an element line");
              if (line.size() < 2)
                reader.fail("an element line must read 'tag nodes...'");
              std::vector<long> nodes;
              for (std::size_t k = 1; k < line.size(); ++k)
                nodes.push_back(reader.integer(line[k], "node tag"));
              builder.add_element(reader.integer(line[0], "element tag"), type, nodes);
            }
        }
      reader.expect("$EndElements");
    }

    std::string lower_case_extension(const std::string &filename)
    {
      const auto dot = filename.find_last_of('.');
      if (dot == std::string::npos || filename.find('/', dot) != std::string::npos)
        return "";
      std::string extension = filename.substr(dot);
      std::transform(extension.begin(), extension.end(), extension.begin(),
                     [](unsigned char c) { return std::tolower(c); });
      return extension;
    }

    double signed_volume(const TetrahedralMesh &mesh, const std::array<unsigned int, 4> &t)
    {
      const auto &p0 = mesh.vertices[t[0]];
      double      e[3][3];
      for (unsigned int a = 1; a < 4; ++a)
        for (unsigned int d = 0; d < 3; ++d)
          e[a - 1][d] = mesh.vertices[t[a]][d] - p0[d];
      return (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
              e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
              e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
             6;
    }

    double longest_edge(const TetrahedralMesh &mesh, const std::array<unsigned int, 4> &t)
    {
      double longest = 0;
      for (unsigned int a = 0; a < 4; ++a)
        for (unsigned int b = a + 1; b < 4; ++b)
          {
            double squared = 0;
            for (unsigned int d = 0; d < 3; ++d)
              squared += std::pow(mesh.vertices[t[a]][d] - mesh.vertices[t[b]][d], 2);
            longest = std::max(longest, std::sqrt(squared));
          }
      return longest;
    }

    /**
     * Throw InputError naming both cells if two tetrahedra of @p mesh have the same four
     * vertices (in any order): the element would count twice in the stiffness and the
     * mass. The pair reported is the first repetition in the file's order.
     */
    void check_no_repeated_tetrahedron(const TetrahedralMesh &mesh)
    {
      // Sorted vertex sets with their cells: a repetition is a run of equal sets.
      std::vector<std::pair<std::array<unsigned int, 4>, std::size_t>> vertex_sets(mesh.tetrahedra.size());
      for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
        {
          vertex_sets[t] = {mesh.tetrahedra[t], t};
          std::sort(vertex_sets[t].first.begin(), vertex_sets[t].first.end());
        }
      std::sort(vertex_sets.begin(), vertex_sets.end());
      std::size_t first = 0, repeated = mesh.tetrahedra.size();
      for (std::size_t k = 1; k < vertex_sets.size(); ++k)
        if (vertex_sets[k].first == vertex_sets[k - 1].first && vertex_sets[k].second < repeated &&
            (k == 1 || vertex_sets[k - 2].first != vertex_sets[k].first))
          {
            first    = vertex_sets[k - 1].second;
            repeated = vertex_sets[k].second;
          }
      if (repeated < mesh.tetrahedra.size())
        throw InputError(mesh.locations[repeated] + " has the four vertices of " + mesh.locations[first] +
                         ": a tetrahedron listed twice would count twice in the stiffness and the mass");
    }
  } // namespace

  TetrahedralMesh read_gmsh(const std::string &filename)
  {
    LineReader      reader(filename);
    GmshMeshBuilder builder(reader);

    const auto &first = reader.next("$NOD or $MeshFormat");
    if (first.size() == 1 && first[0] == "$NOD")
      {
        // Version 1: $NOD ... $ENDNOD $ELM ... $ENDELM.
        read_nodes_v1_v2(reader, builder, "$ENDNOD");
        reader.expect("$ELM");
        read_elements_v1(reader, builder);
        return builder.finish();
      }
    if (first.size() != 1 || first[0] != "$MeshFormat")
      reader.fail("not a Gmsh file: expected $NOD (version 1) or $MeshFormat, found " +
                  reader.joined());

    const auto &format = reader.next("'version file-type data-size'");
    if (format.size() < 3)
      reader.fail("expected 'version file-type data-size', found " + reader.joined());
    const std::string version = format[0];
    if (format[1] != "0")
      reader.fail("binary Gmsh files are not supported (save as ASCII)");
    const bool version_2 = version.rfind("2.", 0) == 0;
    const bool version_4 = version == "4.1";
    if (!version_2 && !version_4)
      reader.fail("Gmsh format version " + quote(version) + " is not supported (1, 2.x and 4.1 are)");
    reader.expect("$EndMeshFormat");

    bool nodes_read = false;
    bool elements_read = false;
    while (!elements_read)
      {
        const auto &line = reader.next(nodes_read ? "$Elements" : "$Nodes");
        if (line.size() != 1 || line[0].empty() || line[0][0] != '$')
          reader.fail("expected a section ($Nodes, $Elements, ...), found " + reader.joined());
        const std::string section = line[0];
        if (section == "$Nodes")
          {
            if (nodes_read)
              reader.fail("a second $Nodes section");
            if (version_2)
              read_nodes_v1_v2(reader, builder, "$EndNodes");
            else
              read_nodes_v4(reader, builder);
            nodes_read = true;
          }
        else if (section == "$Elements")
          {
            if (!nodes_read)
              reader.fail("$Elements before $Nodes");
            if (version_2)
              read_elements_v2(reader, builder);
            else
              read_elements_v4(reader, builder);
            elements_read = true;
          }
        else
          // $PhysicalNames, $Entities, $Periodic, data sections: not needed here.
          reader.skip_to("$End" + section.substr(1));
      }
    return builder.finish();
  }

  void check_and_orient(TetrahedralMesh &mesh)
  {
    if (mesh.tetrahedra.empty())
      throw InputError(mesh.name + ": the mesh has no tetrahedron");
    std::vector<double> volumes(mesh.tetrahedra.size());
    std::size_t         n_negative = 0;
    for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
      {
        volumes[t]         = signed_volume(mesh, mesh.tetrahedra[t]);
        const double scale = longest_edge(mesh, mesh.tetrahedra[t]);
        if (!(std::abs(volumes[t]) > 1e-10 * scale * scale * scale))
          throw InputError(mesh.locations[t] + " is degenerate: volume " +
                           format_number(volumes[t]) + " for edges up to " +
                           format_number(scale));
        if (volumes[t] < 0)
          ++n_negative;
      }
    check_no_repeated_tetrahedron(mesh);
    const std::size_t n_total = mesh.tetrahedra.size();
    if (n_negative == n_total)
      {
        // The file uses the opposite orientation convention: flip every element alike.
        for (auto &tetrahedron : mesh.tetrahedra)
          std::swap(tetrahedron[2], tetrahedron[3]);
        return;
      }
    if (n_negative == 0)
      return;
    // Mixed orientations: the minority is inverted (folded through a neighbour).
    const bool inverted_is_negative = 2 * n_negative <= n_total;
    for (std::size_t t = 0; t < n_total; ++t)
      if ((volumes[t] < 0) == inverted_is_negative)
        throw InputError(mesh.locations[t] + " is inverted: signed volume " +
                         format_number(volumes[t]) + " while " +
                         std::to_string(inverted_is_negative ? n_total - n_negative : n_negative) +
                         " of the " + std::to_string(n_total) +
                         " tetrahedra have the opposite sign");
  }

  MeshFileNumbering create_triangulation(TetrahedralMesh mesh, dealii::Triangulation<3> &triangulation)
  {
    check_and_orient(mesh);

    // Keep the used vertices, in the file's order.
    MeshFileNumbering numbering;
    numbering.vertex_of_file_vertex.assign(mesh.vertices.size(), -1);
    for (const auto &tetrahedron : mesh.tetrahedra)
      for (const unsigned int v : tetrahedron)
        numbering.vertex_of_file_vertex[v] = 0;
    long n_used = 0;
    for (auto &vertex : numbering.vertex_of_file_vertex)
      if (vertex == 0)
        vertex = n_used++;

    // GridIn reads this Gmsh 2.2 stream: tetrahedra only, vertices numbered 1..n_used.
    std::stringstream stream;
    stream << std::setprecision(17);
    stream << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << n_used << "\n";
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
      if (numbering.vertex_of_file_vertex[v] >= 0)
        stream << numbering.vertex_of_file_vertex[v] + 1 << " " << mesh.vertices[v][0] << " "
               << mesh.vertices[v][1] << " " << mesh.vertices[v][2] << "\n";
    stream << "$EndNodes\n$Elements\n" << mesh.tetrahedra.size() << "\n";
    for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
      {
        stream << t + 1 << " 4 0";
        for (const unsigned int v : mesh.tetrahedra[t])
          stream << " " << numbering.vertex_of_file_vertex[v] + 1;
        stream << "\n";
      }
    stream << "$EndElements\n";

    triangulation.clear();
    try
      {
        dealii::GridIn<3> grid_in;
        grid_in.attach_triangulation(triangulation);
        grid_in.read_msh(stream);
      }
    catch (const std::exception &error)
      {
        std::string message = error.what();
        // deal.II's messages span many lines: keep the one that says what went wrong.
        std::istringstream lines(message);
        std::string        line, reason;
        while (std::getline(lines, line))
          if (line.find("Additional information") != std::string::npos &&
              std::getline(lines, reason))
            break;
        throw InputError(mesh.name + ": deal.II could not build a triangulation from the mesh" +
                         (reason.empty() ? std::string() : ": " + reason.substr(reason.find_first_not_of(' '))));
      }
    if (triangulation.n_vertices() != static_cast<unsigned int>(n_used))
      throw InputError(mesh.name + ": deal.II made " + std::to_string(triangulation.n_vertices()) +
                       " vertices out of " + std::to_string(n_used));
    return numbering;
  }

  MeshFormat detect_mesh_format(const std::string &filename)
  {
    std::ifstream input(filename, std::ios::binary);
    char          buffer[256];
    input.read(buffer, sizeof(buffer));
    const std::string start(buffer, input.gcount());
    const auto        first = start.find_first_not_of(" \t\r\n\f\v");
    if (first == std::string::npos)
      return MeshFormat::unknown;
    const auto begins_with = [&](const std::string &prefix) {
      return start.compare(first, prefix.size(), prefix) == 0;
    };
    if (begins_with("$MeshFormat") || begins_with("$NOD"))
      return MeshFormat::gmsh;
    if (begins_with("# vtk DataFile"))
      return MeshFormat::legacy_vtk;
    if (begins_with("<?xml") || begins_with("<VTKFile"))
      return MeshFormat::vtk_xml;
    return MeshFormat::unknown;
  }

  MeshFileNumbering read_mesh(const std::string &filename, dealii::Triangulation<3> &triangulation)
  {
    check_input_file(filename, "mesh file");
    const MeshFormat  format    = detect_mesh_format(filename);
    const std::string extension = lower_case_extension(filename);
    if (format == MeshFormat::gmsh || (format == MeshFormat::unknown && extension == ".msh"))
      return create_triangulation(read_gmsh(filename), triangulation);
    if (format != MeshFormat::unknown || extension == ".vtk" || extension == ".vtu")
      return create_triangulation(read_vtk(filename), triangulation);
    std::ifstream input(filename, std::ios::binary);
    std::string   first_line;
    std::getline(input, first_line);
    throw InputError(filename + ": unknown mesh format: neither its start " + quote(first_line) +
                     " nor its extension '" + excerpt(extension) +
                     "' is Gmsh ($MeshFormat, .msh), legacy VTK (# vtk DataFile, .vtk) or VTK "
                     "XML (<?xml, .vtu)");
  }
} // namespace warpchol::fem
