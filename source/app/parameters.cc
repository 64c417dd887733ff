#include <warpchol/app/parameters.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/input_file.h>

#include <Eigen/Geometry>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace warpchol::app
{
  namespace
  {
    using dealii::ParameterHandler;
    namespace Patterns = dealii::Patterns;

    std::string trim(const std::string &text)
    {
      const auto first = text.find_first_not_of(" \t\r");
      if (first == std::string::npos)
        return "";
      return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
    }


    /** Collapse runs of white space into one blank. */
    std::string one_line(const std::string &text)
    {
      std::istringstream words(text);
      std::string        word, result;
      while (words >> word)
        result += (result.empty() ? "" : " ") + word;
      return result;
    }

    /**
     * deal.II quotes the file's text in its messages: the line that cannot be parsed or
     * the unknown entry between < and >, a value after "The entry value ", a subsection's
     * name at the end. Keep an excerpt() of each, so that the message stays a short line
     * whatever the file holds.
     */
    std::string shorten_quoted_input(const std::string &message)
    {
      std::string result;
      std::size_t position = 0;
      while (position < message.size())
        {
          const auto open = message.find('<', position);
          if (open == std::string::npos)
            break;
          const auto close = message.find('>', open + 1);
          if (close == std::string::npos)
            break;
          result += message.substr(position, open + 1 - position) +
                    excerpt(message.substr(open + 1, close - open - 1), 60) + ">";
          position = close + 1;
        }
      result += message.substr(position);
      for (const auto &[before, after] :
           {std::pair<std::string, std::string>{"The entry value ", " for the entry named "},
            std::pair<std::string, std::string>{"There is no such subsection to be entered: ", ""}})
        {
          const auto begin = result.find(before);
          if (begin == std::string::npos)
            continue;
          const auto start = begin + before.size();
          const auto end   = after.empty() ? result.size() : result.find(after, start);
          if (end != std::string::npos)
            result = result.substr(0, start) + excerpt(result.substr(start, end - start), 60) +
                     result.substr(end);
        }
      // Whatever else deal.II says, on one printable line of a bounded length.
      return excerpt(result, 600);
    }

    /**
     * A parameter file is text: one that looks binary is refused (InputError "@p where: not
     * a parameter file: ...") before deal.II echoes its bytes.
     */
    void refuse_binary(const std::string &filename, const std::string &where)
    {
      std::ifstream input(filename, std::ios::binary);
      std::string   start(4096, '\0');
      input.read(start.data(), start.size());
      start.resize(input.gcount());
      if (looks_binary(start))
        throw InputError(where + ": not a parameter file: it starts with " + quote(start));
    }

    /**
     * ParameterHandler's exceptions carry a several-line message after deal.II's header;
     * keep the "Additional information" as one line, with "Line <N> of file <F>:" written
     * as "F:N:" (the file and line of @p file's text(), an included file's included), and the
     * file's text in it shortened (shorten_quoted_input()).
     */
    std::string parameter_handler_message(const std::exception &error, const ParameterFileLocator &file)
    {
      std::string       message = error.what();
      const std::string marker  = "Additional information:";
      const auto        begin   = message.find(marker);
      if (begin != std::string::npos)
        message = message.substr(begin + marker.size());
      const auto stack = message.find("Stacktrace:");
      if (stack != std::string::npos)
        message.resize(stack);
      message = one_line(message);
      // "Line <N> of file <F>: ...", read by hand: what follows may be long.
      const std::string line_prefix = "Line <", file_prefix = "> of file <";
      // deal.II leaves out the '>' after the file's name in some messages.
      const auto line_end = message.find(file_prefix);
      const auto file_end = line_end == std::string::npos ?
                              std::string::npos :
                              message.find_first_of(">:", line_end + file_prefix.size());
      if (message.rfind(line_prefix, 0) == 0 && file_end != std::string::npos)
        {
          const std::string line = message.substr(line_prefix.size(), line_end - line_prefix.size());
          const std::string file_name = message.substr(line_end + file_prefix.size(),
                                                       file_end - line_end - file_prefix.size());
          std::string rest = message.substr(file_end);
          if (!rest.empty() && rest[0] == '>')
            rest.erase(0, 1);
          if (!rest.empty() && rest[0] == ':')
            rest.erase(0, 1);
          if (!rest.empty() && rest[0] == ' ')
            rest.erase(0, 1);
          // A line of the text with its includes written out: the file and line it is.
          const std::string where = file_name == file.filename() && !line.empty() && line.size() < 10 &&
                                        line.find_first_not_of("0123456789") == std::string::npos ?
                                      file.origin(std::stoi(line)) :
                                      file_name + ":" + line;
          return where + ": " + shorten_quoted_input(rest);
        }
      return shorten_quoted_input(message);
    }

    const auto vector_pattern = Patterns::List(Patterns::Double(), 3, 3, ",");

    fem::Vector3 get_vector(ParameterHandler &prm, const std::string &entry)
    {
      const auto   parts = dealii::Utilities::split_string_list(prm.get(entry), ',');
      fem::Vector3 result;
      for (unsigned int d = 0; d < 3; ++d)
        result[d] = dealii::Utilities::string_to_double(parts[d]);
      return result;
    }

    void require_positive(ParameterHandler &prm, const ParameterFileLocator &file,
                          const std::string &subsection, const std::string &entry)
    {
      if (!(prm.get_double(entry) > 0))
        file.fail(prm, subsection, entry, "must be > 0");
    }

    /** The entry "Path file" of an instrument, in the current subsection; @p effect: what it does. */
    void declare_path_file(ParameterHandler &prm, const std::string &effect)
    {
      prm.declare_entry("Path file", "", Patterns::Anything(),
                        "A recorded path (CSV, relative to this file; empty: none), linear between its "
                        "samples: " + effect);
    }

    /** The entry "Path file" (trimmed); with one, the instrument must not also move with @p velocity. */
    std::string parse_path_file(ParameterHandler &prm, const ParameterFileLocator &file,
                                const std::string &subsection, const fem::Vector3 &velocity)
    {
      const std::string name = trim(prm.get("Path file"));
      if (!name.empty() && velocity.norm() > 0)
        file.fail(prm, subsection, "Velocity", "must be 0 with a Path file: the path moves the instrument");
      return name;
    }

    /**
     * The numbered events a parameter file's @p text holds ("subsection Cut 2", "Grasp 3",
     * "Material change 2", ...), in the order of their numbers: they are declared as the
     * first ones are, so that any number of them can be set. A number below 2 is left
     * undeclared (the first event is the subsection without a number): ParameterHandler
     * names it as an unknown subsection.
     */
    std::vector<std::string> numbered_events(const std::string &text, const std::string &kind)
    {
      std::vector<unsigned long> numbers;
      std::istringstream         lines(text);
      for (std::string line; std::getline(lines, line);)
        {
          std::istringstream words(line);
          std::string        word, name;
          if (!(words >> word) || word != "subsection")
            continue;
          std::getline(words, name);
          name = trim(name);
          if (name.size() <= kind.size() + 1 || name.compare(0, kind.size() + 1, kind + " ") != 0)
            continue;
          const std::string number = trim(name.substr(kind.size() + 1));
          if (number.empty() || number.size() > 6 ||
              !std::all_of(number.begin(), number.end(), [](const unsigned char c) { return std::isdigit(c); }) ||
              number[0] == '0' || std::stoul(number) < 2)
            continue;
          numbers.push_back(std::stoul(number));
        }
      std::sort(numbers.begin(), numbers.end());
      numbers.erase(std::unique(numbers.begin(), numbers.end()), numbers.end());
      std::vector<std::string> names;
      for (const unsigned long n : numbers)
        names.push_back(kind + " " + std::to_string(n));
      return names;
    }
  } // namespace

  // ---------------------------------------------------------------------------------------
  ParameterFileLocator::ParameterFileLocator(const std::string &filename)
    : file(filename)
    , files{filename}
  {
    std::vector<std::string> subsections;
    std::error_code          error;
    std::vector<std::string> chain{std::filesystem::weakly_canonical(filename, error).string()};
    read(0, subsections, chain);
  }

  namespace
  {
    /** The folder of @p filename with its '/', "" for the working directory. */
    std::string folder_of(const std::string &filename)
    {
      const auto slash = filename.find_last_of('/');
      return slash == std::string::npos ? std::string() : filename.substr(0, slash + 1);
    }
  } // namespace

  void ParameterFileLocator::read(const unsigned int file_index, std::vector<std::string> &subsections,
                                  std::vector<std::string> &chain)
  {
    // Copied: files grows while the includes are read.
    const std::string name = files[file_index];
    std::ifstream     input(name);
    int               line_number = 0;
    bool              continued   = false;
    for (std::string line; std::getline(input, line);)
      {
        ++line_number;
        const std::string statement = trim(line.substr(0, line.find('#')));
        const std::string first     = statement.substr(0, statement.find_first_of(" \t"));
        const std::string rest      = trim(statement.substr(first.size()));
        // A line that ends in a backslash goes on in the next: that one starts no statement.
        const bool continuation = continued;
        continued               = !trim(line).empty() && trim(line).back() == '\\';
        if (continuation || (first != "include" && first != "INCLUDE"))
          {
            expanded_text += line + "\n";
            line_origins.emplace_back(file_index, line_number);
            if (continuation)
              continue;
            if (first == "subsection")
              subsections.push_back(one_line(rest));
            else if (first == "end" && !subsections.empty())
              subsections.pop_back();
            else if (first == "set")
              {
                std::string path;
                for (const auto &subsection : subsections)
                  path += subsection + "/";
                set_lines.emplace_back(path + one_line(rest.substr(0, rest.find('='))),
                                       static_cast<int>(line_origins.size()));
              }
            continue;
          }

        // Relative to the folder of this file, as every path a parameter file holds.
        const std::string included = rest.empty() || rest[0] == '/' ? rest : folder_of(name) + rest;
        const std::string where = name + ":" + std::to_string(line_number) + ": include " + quote(rest);
        struct stat       status;
        if (::stat(included.c_str(), &status) != 0)
          throw InputError(where + ": cannot open it");
        if (!S_ISREG(status.st_mode))
          throw InputError(where + ": not a regular file");
        refuse_binary(included, where);
        std::error_code   error;
        const std::string path = std::filesystem::weakly_canonical(included, error).string();
        if (std::find(chain.begin(), chain.end(), path) != chain.end())
          throw InputError(where + ": it is already being read (a cycle of includes)");
        // deal.II requires an included file to close the subsections it opens.
        const std::vector<std::string> open_before = subsections;
        chain.push_back(path);
        files.push_back(included);
        read(files.size() - 1, subsections, chain);
        chain.pop_back();
        if (subsections != open_before)
          throw InputError(where + ": its 'subsection' and 'end' statements do not pair up");
      }
  }

  const std::string &ParameterFileLocator::text() const
  {
    return expanded_text;
  }

  std::string ParameterFileLocator::origin(const int line) const
  {
    if (line < 1 || line > static_cast<int>(line_origins.size()))
      return file + ":" + std::to_string(line);
    const auto &[file_index, file_line] = line_origins[line - 1];
    return files[file_index] + ":" + std::to_string(file_line);
  }

  std::string ParameterFileLocator::where(const std::string &subsection,
                                          const std::string &entry) const
  {
    const std::string path = subsection + "/" + entry;
    if (file.empty())
      return "defaults: " + path;
    for (auto set = set_lines.rbegin(); set != set_lines.rend(); ++set)
      if (set->first == path)
        return origin(set->second) + ": " + path;
    return file + ": " + path + " (default)";
  }

  void ParameterFileLocator::fail(const dealii::ParameterHandler &prm,
                                  const std::string &subsection, const std::string &entry,
                                  const std::string &message) const
  {
    // The value comes from the file: an excerpt of it, printable.
    throw InputError(where(subsection, entry) + " = " + excerpt(prm.get(entry), 60) + ": " + message);
  }

  std::string ParameterFileLocator::directory_of(const std::string &subsection, const std::string &entry) const
  {
    const std::string path = subsection + "/" + entry;
    for (auto set = set_lines.rbegin(); set != set_lines.rend(); ++set)
      if (set->first == path)
        return folder_of(files[line_origins[set->second - 1].first]);
    return folder_of(file);
  }

  const std::string &ParameterFileLocator::filename() const
  {
    return file;
  }

  // ---------------------------------------------------------------------------------------
  bool parse_threshold(const std::string &text, double &threshold)
  {
    const std::string value = trim(text);
    if (value == "inf" || value == "infinity")
      {
        threshold = std::numeric_limits<double>::infinity();
        return true;
      }
    std::size_t used = 0;
    try
      {
        threshold = std::stod(value, &used);
      }
    catch (...)
      {
        return false;
      }
    return !value.empty() && used == value.size() && threshold >= 0 && !std::isinf(threshold);
  }

  void RegionParameters::declare_parameters(ParameterHandler &prm, const std::string &what,
                                            const std::string &default_kind)
  {
    prm.declare_entry("Region", default_kind, Patterns::Selection("none|box|sphere|ids"),
                      "The vertices " + what + ": none, those in a box or a sphere (rest "
                      "positions), or those listed in Vertex ids");
    prm.declare_entry("Box lower corner", "0, 0, 0", vector_pattern,
                      "Region = box: the corner with the smallest coordinates (m)");
    prm.declare_entry("Box upper corner", "0, 0, 0", vector_pattern,
                      "Region = box: the corner with the largest coordinates (m)");
    prm.declare_entry("Sphere center", "0, 0, 0", vector_pattern,
                      "Region = sphere: the centre (m)");
    prm.declare_entry("Sphere radius", "0", Patterns::Double(0),
                      "Region = sphere: the radius (m)");
    prm.declare_entry("Vertex ids", "", Patterns::List(Patterns::Integer(0), 0, Patterns::List::max_int_value, ","),
                      "Region = ids: vertex ids counted from 0 in the order of the mesh "
                      "file's node list (SOFA's numbering), or of a generated mesh's vertices");
  }

  void RegionParameters::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file,
                                          const std::string &subsection)
  {
    kind             = prm.get("Region");
    box_lower_corner = get_vector(prm, "Box lower corner");
    box_upper_corner = get_vector(prm, "Box upper corner");
    sphere_center    = get_vector(prm, "Sphere center");
    sphere_radius    = prm.get_double("Sphere radius");
    vertex_ids.clear();
    for (const auto &id : dealii::Utilities::split_string_list(prm.get("Vertex ids"), ','))
      vertex_ids.push_back(dealii::Utilities::string_to_int(id));
    if (kind == "box" && !(box_upper_corner.array() >= box_lower_corner.array()).all())
      file.fail(prm, subsection, "Box upper corner",
                "must not lie below Box lower corner along any axis");
    if (kind == "sphere")
      require_positive(prm, file, subsection, "Sphere radius");
    if (kind == "ids" && vertex_ids.empty())
      file.fail(prm, subsection, "Vertex ids", "Region = ids needs at least one id");
  }

  // ---------------------------------------------------------------------------------------
  namespace parameters
  {
    void Mesh::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Mesh");
      prm.declare_entry("Source", "torus", Patterns::Selection("torus|box|cylinder|tube|file"),
                        "torus, box, cylinder or tube: generated by deal.II and split into "
                        "tetrahedra; file: read from File");
      prm.declare_entry("File", "", Patterns::Anything(),
                        "Source = file: a tetrahedral mesh (.msh Gmsh 1, 2.2 or 4.1 ASCII, .vtk "
                        "legacy VTK, .vtu VTK XML); a relative name is taken relative to the "
                        "folder of the parameter file that sets it (an included one's own)");
      prm.declare_entry("Scale", "1", Patterns::Double(0),
                        "Source = file: factor applied to the file's coordinates");
      prm.declare_entry("Refinements", "0", Patterns::Integer(0, 4),
                        "Source = file: global refinements of the mesh read (deal.II's: each "
                        "tetrahedron into 8); a vertex id of the file keeps its vertex");
      prm.declare_entry("Torus major radius", "0.3", Patterns::Double(0),
                        "Radius of the torus' centre line (m); the torus turns around the y axis");
      prm.declare_entry("Torus minor radius", "0.1", Patterns::Double(0),
                        "Radius of the torus' cross-section (m)");
      prm.declare_entry("Torus toroidal cells", "12", Patterns::Integer(3, 1000),
                        "Hexahedral layers around the torus before refinement (each hexahedron "
                        "becomes 24 tetrahedra)");
      prm.declare_entry("Torus refinements", "0", Patterns::Integer(0, 4),
                        "Global refinements of the hexahedral torus before the split");
      prm.declare_entry("Box lower corner", "0, 0, 0", vector_pattern,
                        "Source = box: the corner with the smallest coordinates (m)");
      prm.declare_entry("Box upper corner", "0.4, 0.1, 0.1", vector_pattern,
                        "Source = box: the corner with the largest coordinates (m)");
      prm.declare_entry("Box subdivisions", "8, 2, 2",
                        Patterns::List(Patterns::Integer(1, 1000), 3, 3, ","),
                        "Source = box: hexahedra along x, y, z (each becomes 24 tetrahedra)");
      prm.declare_entry("Box grading", "1", Patterns::Double(1),
                        "Source = box: >= 1; the hexahedra grow geometrically along every axis, "
                        "the last this many times as long as the first (a graded mesh whose "
                        "element sizes span this factor)");
      prm.declare_entry("Box sliver flattening", "1", Patterns::Double(0, 1),
                        "Source = box: in (0, 1]; below 1, each hexahedron becomes the 6 "
                        "tetrahedra around its main diagonal and the box is flattened by this "
                        "factor along (-1, 0, 1): slivers, flat tetrahedra without a short edge "
                        "(a parallelepiped body)");
      prm.declare_entry("Cylinder radius", "0.025", Patterns::Double(0),
                        "Source = cylinder: a solid rod along x from x = 0 to its length (m)");
      prm.declare_entry("Cylinder length", "1", Patterns::Double(0), "Source = cylinder: its length (m)");
      prm.declare_entry("Cylinder axial cells", "20", Patterns::Integer(1, 10000),
                        "Source = cylinder: layers of hexahedra along the axis before refinement "
                        "(the cross-section has 5; each hexahedron becomes 24 tetrahedra)");
      prm.declare_entry("Cylinder refinements", "1", Patterns::Integer(0, 4),
                        "Source = cylinder: global refinements of the hexahedra before the split");
      prm.declare_entry("Tube inner radius", "0.004", Patterns::Double(0),
                        "Source = tube: a vessel along z from z = 0 to its length (m)");
      prm.declare_entry("Tube outer radius", "0.005", Patterns::Double(0), "Source = tube (m)");
      prm.declare_entry("Tube length", "0.1", Patterns::Double(0), "Source = tube (m)");
      prm.declare_entry("Tube circumferential cells", "12", Patterns::Integer(3, 10000),
                        "Source = tube: hexahedra around the wall (one through it) before refinement");
      prm.declare_entry("Tube axial cells", "20", Patterns::Integer(1, 10000),
                        "Source = tube: hexahedra along the axis before refinement");
      prm.declare_entry("Tube refinements", "0", Patterns::Integer(0, 4),
                        "Source = tube: global refinements of the hexahedra before the split");
      prm.leave_subsection();
    }

    void Mesh::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Mesh");
      source    = prm.get("Source");
      file_name = prm.get("File");
      scale     = prm.get_double("Scale");
      refinements = prm.get_integer("Refinements");
      if (source == "file" && file_name.empty())
        file.fail(prm, "Mesh", "File", "Source = file needs a mesh file");
      require_positive(prm, file, "Mesh", "Scale");
      torus.major_radius   = prm.get_double("Torus major radius");
      torus.minor_radius   = prm.get_double("Torus minor radius");
      torus.toroidal_cells = prm.get_integer("Torus toroidal cells");
      torus.refinements    = prm.get_integer("Torus refinements");
      if (source == "torus")
        {
          require_positive(prm, file, "Mesh", "Torus minor radius");
          if (!(torus.major_radius > torus.minor_radius))
            file.fail(prm, "Mesh", "Torus major radius", "must exceed Torus minor radius");
        }
      const fem::Vector3 lower = get_vector(prm, "Box lower corner");
      const fem::Vector3 upper = get_vector(prm, "Box upper corner");
      if (source == "box" && !(upper.array() > lower.array()).all())
        file.fail(prm, "Mesh", "Box upper corner", "must lie above Box lower corner along every axis");
      box.grading           = prm.get_double("Box grading");
      box.sliver_flattening = prm.get_double("Box sliver flattening");
      if (!(box.sliver_flattening > 0))
        file.fail(prm, "Mesh", "Box sliver flattening", "must be > 0 (a flat box has no volume)");
      cylinder.radius      = prm.get_double("Cylinder radius");
      cylinder.length      = prm.get_double("Cylinder length");
      cylinder.axial_cells = prm.get_integer("Cylinder axial cells");
      cylinder.refinements = prm.get_integer("Cylinder refinements");
      if (source == "cylinder")
        {
          require_positive(prm, file, "Mesh", "Cylinder radius");
          require_positive(prm, file, "Mesh", "Cylinder length");
        }
      tube.inner_radius          = prm.get_double("Tube inner radius");
      tube.outer_radius          = prm.get_double("Tube outer radius");
      tube.length                = prm.get_double("Tube length");
      tube.circumferential_cells = prm.get_integer("Tube circumferential cells");
      tube.axial_cells           = prm.get_integer("Tube axial cells");
      tube.refinements           = prm.get_integer("Tube refinements");
      if (source == "tube")
        {
          require_positive(prm, file, "Mesh", "Tube inner radius");
          require_positive(prm, file, "Mesh", "Tube length");
          if (!(tube.outer_radius > tube.inner_radius))
            file.fail(prm, "Mesh", "Tube outer radius", "must exceed Tube inner radius");
        }
      const auto subdivisions = dealii::Utilities::split_string_list(prm.get("Box subdivisions"), ',');
      for (unsigned int d = 0; d < 3; ++d)
        {
          box.lower_corner[d] = lower[d];
          box.upper_corner[d] = upper[d];
          box.subdivisions[d] = dealii::Utilities::string_to_int(subdivisions[d]);
        }
      prm.leave_subsection();
    }

    void Material::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Material");
      prm.declare_entry("Young's modulus", "50", Patterns::Double(0),
                        "E (Pa), > 0: isotropic linear elasticity");
      prm.declare_entry("Poisson's ratio", "0.45", Patterns::Double(-1, 0.5),
                        "nu, in (-1, 0.5): incompressible (0.5) is not supported");
      prm.declare_entry("Density", "20", Patterns::Double(0),
                        "Mass density (kg/m^3), > 0; unused when Total mass > 0");
      prm.declare_entry("Total mass", "0", Patterns::Double(0),
                        "If > 0, the body's mass (kg): the density is this over the mesh volume");
      prm.declare_entry("Mass matrix", "lumped", Patterns::Selection("lumped|consistent"),
                        "lumped (row sums, one mass per vertex) or consistent (Galerkin)");
      prm.leave_subsection();
    }

    void Material::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Material");
      youngs_modulus = prm.get_double("Young's modulus");
      poisson_ratio  = prm.get_double("Poisson's ratio");
      density        = prm.get_double("Density");
      total_mass     = prm.get_double("Total mass");
      mass_matrix = prm.get("Mass matrix") == "lumped" ? fem::MassMatrix::lumped : fem::MassMatrix::consistent;
      require_positive(prm, file, "Material", "Young's modulus");
      if (!(poisson_ratio < 0.5))
        file.fail(prm, "Material", "Poisson's ratio",
                  "must be < 0.5 (an incompressible material makes lambda infinite)");
      if (!(poisson_ratio > -1))
        file.fail(prm, "Material", "Poisson's ratio", "must be > -1");
      if (total_mass == 0)
        require_positive(prm, file, "Material", "Density");
      prm.leave_subsection();
    }

    void TimeStepping::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Time stepping");
      prm.declare_entry("Time step", "0.01", Patterns::Double(0), "dt (s), > 0: implicit Euler");
      prm.declare_entry("Number of steps", "100", Patterns::Integer(1), "Steps to run");
      prm.declare_entry("Rayleigh mass", "0", Patterns::Double(0),
                        "alpha (1/s) in the damping matrix B = alpha M + beta K");
      prm.declare_entry("Rayleigh stiffness", "0", Patterns::Double(0),
                        "beta (s) in the damping matrix B = alpha M + beta K");
      prm.declare_entry("Rest kinetic energy", "0", Patterns::Double(0),
                        "If > 0, stop once the kinetic energy (J) falls below it after the "
                        "first step: the body is at rest. Needs a fixed vertex when gravity or "
                        "a region force acts (otherwise the body never comes to rest)");
      prm.declare_entry("Energy growth limit", "10", Patterns::Double(0),
                        "Stop with an error (status 1) once the energy the body holds "
                        "(kinetic, elastic, tool springs) exceeds this many times the energy "
                        "put into it (initial energy, work of the tool and of gravity and the "
                        "region force): a diverging simulation. Implicit Euler dissipates, so a "
                        "stable run stays at or below 1; 0: never stop");
      prm.leave_subsection();
    }

    void TimeStepping::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Time stepping");
      time_step           = prm.get_double("Time step");
      n_steps             = prm.get_integer("Number of steps");
      rayleigh_mass       = prm.get_double("Rayleigh mass");
      rayleigh_stiffness  = prm.get_double("Rayleigh stiffness");
      rest_kinetic_energy = prm.get_double("Rest kinetic energy");
      energy_growth_limit = prm.get_double("Energy growth limit");
      require_positive(prm, file, "Time stepping", "Time step");
      if (energy_growth_limit > 0 && energy_growth_limit < 1)
        file.fail(prm, "Time stepping", "Energy growth limit",
                  "must be 0 (off) or >= 1: a stable run may hold all the energy put in");
      prm.leave_subsection();
    }

    void Model::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Model");
      prm.declare_entry("Type", "warp_canceling",
                        Patterns::Selection("linear|corotational|stiffness_warping|warp_canceling"),
                        "linear: no rotation, factor once; corotational: exact per-element "
                        "rotations, refactor every step; stiffness_warping: nodal rotations, "
                        "factor once; warp_canceling: WCC, partial refactorization of the "
                        "columns of the elements whose error estimate exceeds the threshold");
      prm.declare_entry("Update threshold", "0.05", Patterns::Anything(),
                        "warp_canceling: a number >= 0 or inf. An element is updated when its "
                        "error estimate (an impulse) exceeds this fraction of the step's impulse "
                        "scale: the mean over elements of |A_e v_e| + dt |f_e| (dimensionless). "
                        "0 updates all (exact corotation), inf none (stiffness warping)");
      prm.declare_entry("Target error", "0", Patterns::Double(0, 1),
                        "warp_canceling: > 0 adapts the update threshold every step, from "
                        "Update threshold, so that the trajectory error (max vertex error "
                        "against exact corotation over the largest displacement) stays near "
                        "this: each step measures its velocity error against exact corotation "
                        "(a matrix-free product and a solve) and the threshold follows to keep "
                        "it at half the target. 0: the threshold stays fixed. Needs Strategy = "
                        "partial or Iterate on = warp_canceling");
      prm.declare_entry("Strategy", "partial", Patterns::Anything(),
                        "warp_canceling: how a step keeps the factor up to date and solves. "
                        "partial: partial refactorization of every column that depends on an "
                        "update, direct solve (the WCC system exactly); preconditioned: the same "
                        "factor as the preconditioner of CG on the 'Iterate on' matrix; "
                        "delayed_top: every step only the supernodes below the top of the "
                        "elimination tree (Solver/Top flops fraction), the top every 'Refresh "
                        "interval' steps or after a solve of more than 'Refresh iterations' "
                        "iterations, CG; auto: per step the cheapest of refreshing all, below "
                        "the top or nothing, by a cost model of measured rates, CG; background: "
                        "the matrix with every element updated is assembled and factored on a "
                        "thread of its own beside the steps, which solve by CG preconditioned "
                        "with the last factor that finished (Background lag; the threshold is "
                        "not used)");
      prm.declare_entry("Iterate on", "corotational", Patterns::Anything(),
                        "The matrix CG solves with (all strategies but partial): corotational "
                        "(the exact corotational matrix, matrix-free: the WCC error becomes "
                        "iterations) or warp_canceling (the assembled WCC matrix)");
      prm.declare_entry("CG tolerance", "1e-3", Patterns::Double(1e-15, 1),
                        "CG stops when |b - B x| <= this times |b|");
      prm.declare_entry("Max CG iterations", "100", Patterns::Integer(1, 100000),
                        "A solve that needs more refreshes the whole factor and starts again");
      prm.declare_entry("Refresh interval", "10", Patterns::Integer(1, 1000000),
                        "delayed_top: the top is refreshed at least every this many steps");
      prm.declare_entry("Refresh iterations", "8", Patterns::Integer(1, 100000),
                        "delayed_top: and in the step after a solve that needed more "
                        "iterations than this");
      prm.declare_entry("Background lag", "0", Patterns::Integer(0, 1000000),
                        "background: 0, a refresh is taken at the first step after it finished "
                        "(as fast as the machine allows; the trajectory depends on the timing "
                        "to the CG tolerance); N > 0, the refresh started at step k is taken at "
                        "step k + N, the step waiting for it if need be (deterministic: the same "
                        "bits on any machine and thread count, checkpoints resume exactly)");
      prm.leave_subsection();
    }

    void Model::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Model");
      type                   = prm.get("Type");
      if (!parse_threshold(prm.get("Update threshold"), update_threshold))
        file.fail(prm, "Model", "Update threshold", "must be a number >= 0 or inf");
      try
        {
          strategy.kind = fem::parse_step_strategy(trim(prm.get("Strategy")));
        }
      catch (const Error &error)
        {
          file.fail(prm, "Model", "Strategy", error.what());
        }
      try
        {
          strategy.iterate_on = fem::parse_iteration_target(trim(prm.get("Iterate on")));
        }
      catch (const Error &error)
        {
          file.fail(prm, "Model", "Iterate on", error.what());
        }
      target_error                = prm.get_double("Target error");
      if (target_error > 0 && type == "warp_canceling" &&
          (!(update_threshold > 0) || std::isinf(update_threshold)))
        file.fail(prm, "Model", "Target error",
                  "adapts the update threshold, which must then start finite and > 0 (Update "
                  "threshold = " + format_number(update_threshold) + ")");
      strategy.cg_tolerance       = prm.get_double("CG tolerance");
      strategy.max_cg_iterations  = prm.get_integer("Max CG iterations");
      strategy.refresh_interval   = prm.get_integer("Refresh interval");
      strategy.refresh_iterations = prm.get_integer("Refresh iterations");
      strategy.background_lag     = prm.get_integer("Background lag");
      prm.leave_subsection();
    }

    Solver::Solver()
    {
      settings.method = cholesky::FactorizationMethod::supernodal;
    }

    void Solver::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Solver");
      prm.declare_entry("Ordering", "metis", Patterns::Anything(),
                        "Fill-reducing ordering of the sparse Cholesky solver: natural, amd or "
                        "metis (nested dissection: the best for partial refactorizations)");
      prm.declare_entry("Method", "supernodal", Patterns::Anything(),
                        "Numeric factorization of the sparse Cholesky solver: supernodal "
                        "(left-looking by supernodes with BLAS-3 kernels, refactorizes "
                        "partially), left_looking (column by column, refactorizes partially) or "
                        "up_looking (CSparse's, always in full)");
      prm.declare_entry("Threads", "1", Patterns::Integer(1, 1024),
                        "Threads of the supernodal factorization and of the element loops "
                        "(rotations, error estimates); 1: serial");
      prm.declare_entry("Top flops fraction", "0.5", Patterns::Double(0, 1),
                        "The top of the elimination tree that Model/Strategy = delayed_top or "
                        "auto may leave stale: the smallest upward-closed set of supernodes "
                        "holding this fraction of the factorization flops");
      prm.declare_entry("Backend", "warpchol", Patterns::Anything(),
                        "Who factors and solves each step's system: warpchol (this project's "
                        "factor, refactorized partially), or a peer: cholmod (CHOLMOD "
                        "supernodal, its own ordering), umfpack (deal.II's SparseDirectUMFPACK), "
                        "eigen (Eigen's SimplicialLLT), eigen_cholmod (Eigen's CHOLMOD "
                        "wrapper), each refactorizing in full every step; trilinos_amg_cg "
                        "(Trilinos CG with an ML AMG preconditioner set up once, rigid-body "
                        "modes as near null space); warp_preconditioned_cg (SOFA's: CG on the "
                        "corotational matrix, the rest factor rotated by the nodal rotations "
                        "as preconditioner; Model/Type = corotational)");
      prm.declare_entry("Tolerance", "1e-6", Patterns::Double(0),
                        "The iterative backends (trilinos_amg_cg, warp_preconditioned_cg) stop "
                        "at |b - A x| <= Tolerance |b|");
      prm.declare_entry("Max iterations", "1000", Patterns::Integer(1),
                        "The iterative backends fail past this many iterations");
      prm.declare_entry("Change method", "auto", Patterns::Selection("auto|flops|recompute|update"),
                        "How a change of A (a grasp, a cut, a material change, WCC's re-rotated "
                        "elements) reaches an exact factor (supernodal method): auto takes the "
                        "cheaper of an update of the factor by the change in low-rank form and "
                        "the recomputation of the columns on its paths, by their predicted "
                        "seconds at rates measured during the run; flops the same at fixed "
                        "rates (the same choices on any machine: reproducible bits); recompute "
                        "never updates; update always does where it can");
      prm.declare_entry("Preconditioner precision", "double", Patterns::Selection("double|single|half"),
                        "The factor as CG's preconditioner (Model/Strategy other than partial, "
                        "supernodal method): single keeps a copy of L in 32 bits per entry, half "
                        "in 16 (IEEE half, each column scaled by a power of two), and solves "
                        "with it in single precision: a half or a quarter of the memory traffic "
                        "of the memory-bound triangular solves. CG's tolerance then should stay "
                        "above about 1e-6 (single) or 1e-3 (half: the preconditioner is a 5e-4 "
                        "relative rounding of L, CG corrects it in its iterations)");
      prm.leave_subsection();
    }

    void Solver::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Solver");
      try
        {
          settings.ordering.method = cholesky::parse_ordering_method(trim(prm.get("Ordering")));
        }
      catch (const Error &error)
        {
          file.fail(prm, "Solver", "Ordering", error.what());
        }
      try
        {
          settings.method = cholesky::parse_factorization_method(trim(prm.get("Method")));
        }
      catch (const Error &error)
        {
          file.fail(prm, "Solver", "Method", error.what());
        }
      try
        {
          backend.backend = backends::parse_backend(trim(prm.get("Backend")));
        }
      catch (const Error &error)
        {
          file.fail(prm, "Solver", "Backend", error.what());
        }
      backend.tolerance      = prm.get_double("Tolerance");
      backend.max_iterations = prm.get_integer("Max iterations");
      if (!(backend.tolerance > 0 && backend.tolerance < 1))
        file.fail(prm, "Solver", "Tolerance", "must be in (0, 1)");
      settings.n_threads          = prm.get_integer("Threads");
      settings.top_flops_fraction = prm.get_double("Top flops fraction");
      const std::string precision       = prm.get("Preconditioner precision");
      settings.preconditioner_precision = precision == "single" ? cholesky::PreconditionerPrecision::single :
                                          precision == "half"   ? cholesky::PreconditionerPrecision::half :
                                                                  cholesky::PreconditionerPrecision::full;
      settings.change_method            = cholesky::parse_change_method(prm.get("Change method"));
      prm.leave_subsection();
    }

    void InitialState::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Initial state");
      prm.declare_entry("Linear velocity", "0, 0, 0", vector_pattern,
                        "Initial velocity (m/s) of every vertex that is not fixed");
      prm.declare_entry("Angular velocity", "0, 0, 0", vector_pattern,
                        "Initial angular velocity (rad/s, a vector along the axis) about the "
                        "rest centre of mass, added to the linear velocity: a spinning body");
      prm.leave_subsection();
    }

    void InitialState::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &)
    {
      prm.enter_subsection("Initial state");
      linear_velocity  = get_vector(prm, "Linear velocity");
      angular_velocity = get_vector(prm, "Angular velocity");
      prm.leave_subsection();
    }

    void FixedVertices::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Fixed vertices");
      RegionParameters::declare_parameters(prm, "held at rest (their dofs are not unknowns)");
      prm.leave_subsection();
    }

    void FixedVertices::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Fixed vertices");
      region.parse_parameters(prm, file, "Fixed vertices");
      prm.leave_subsection();
    }

    void Gravity::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Gravity");
      prm.declare_entry("Acceleration", "0, 0, 0", vector_pattern,
                        "Gravitational acceleration (m/s^2), e.g. 0, -9.81, 0");
      prm.leave_subsection();
    }

    void Gravity::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &)
    {
      prm.enter_subsection("Gravity");
      acceleration = get_vector(prm, "Acceleration");
      prm.leave_subsection();
    }

    void RegionForce::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Region force");
      RegionParameters::declare_parameters(prm, "that carry the force");
      prm.declare_entry("Total force", "0, 0, 0", vector_pattern,
                        "A constant force (N) on the region, shared by its vertices in proportion to "
                        "their masses (a body force)");
      prm.leave_subsection();
    }

    void RegionForce::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Region force");
      region.parse_parameters(prm, file, "Region force");
      total_force = get_vector(prm, "Total force");
      prm.leave_subsection();
    }

    void Tool::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Tool");
      RegionParameters::declare_parameters(prm, "the tool grabs");
      prm.declare_entry("Spring stiffness", "0", Patterns::Double(0),
                        "Stiffness (N/m) of the spring tying each grabbed vertex to its target");
      prm.declare_entry("Velocity", "0, 0, 0", vector_pattern,
                        "Velocity (m/s) of the targets, which start at the grabbed vertices' "
                        "rest positions");
      prm.declare_entry("Duration", "0", Patterns::Double(0),
                        "Time (s) after which the targets stop and hold");
      declare_path_file(prm, "the targets move as its positions do from time 0 (its samples must "
                             "cover the run), instead of with Velocity");
      prm.leave_subsection();
    }

    void Tool::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Tool");
      region.parse_parameters(prm, file, "Tool");
      spring_stiffness = prm.get_double("Spring stiffness");
      velocity         = get_vector(prm, "Velocity");
      duration         = prm.get_double("Duration");
      if (region.kind != "none")
        require_positive(prm, file, "Tool", "Spring stiffness");
      path.file_name = parse_path_file(prm, file, "Tool", velocity);
      prm.leave_subsection();
    }

    bool Cut::active() const
    {
      return duration > 0 && (velocity.norm() > 0 || !path.file_name.empty());
    }

    void Cut::declare_parameters(ParameterHandler &prm, const std::string &subsection)
    {
      prm.enter_subsection(subsection);
      prm.declare_entry("Blade start", "0, 0, 0", vector_pattern,
                        "One end of the blade's cutting edge (m) at Start time");
      prm.declare_entry("Blade end", "0, 0, 0", vector_pattern, "The other end of the cutting edge (m)");
      prm.declare_entry("Velocity", "0, 0, 0", vector_pattern,
                        "Velocity (m/s) of the edge: every tetrahedron the area it sweeps in a step "
                        "crosses is cut at that step (its stiffness and mass leave A)");
      prm.declare_entry("Start time", "0", Patterns::Double(0), "When the blade starts moving (s)");
      prm.declare_entry("Duration", "0", Patterns::Double(0),
                        "How long it moves (s); 0: no cut");
      declare_path_file(prm, "lines of time, start x, y, z, end x, y, z: the edge follows it from Start "
                             "time for Duration, instead of Blade start, Blade end and Velocity");
      prm.leave_subsection();
    }

    void Cut::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file, const std::string &subsection)
    {
      this->subsection = subsection;
      prm.enter_subsection(subsection);
      blade_start    = get_vector(prm, "Blade start");
      blade_end      = get_vector(prm, "Blade end");
      velocity       = get_vector(prm, "Velocity");
      start_time     = prm.get_double("Start time");
      duration       = prm.get_double("Duration");
      path.file_name = parse_path_file(prm, file, subsection, velocity);
      if (path.file_name.empty())
        {
          if (duration > 0 && !((blade_end - blade_start).norm() > 0))
            file.fail(prm, subsection, "Blade end", "must differ from Blade start: the edge has no length");
          if (duration > 0 && !(velocity.norm() > 0))
            file.fail(prm, subsection, "Velocity", "must not be zero while the blade cuts (Duration > 0)");
          if (duration > 0 && velocity.cross(blade_end - blade_start).norm() <=
                                1e-12 * velocity.norm() * (blade_end - blade_start).norm())
            file.fail(prm, subsection, "Velocity", "runs along the edge: the blade would sweep no area");
        }
      prm.leave_subsection();
    }

    bool Grasp::active() const
    {
      return sphere_radius > 0;
    }

    void Grasp::declare_parameters(ParameterHandler &prm, const std::string &subsection)
    {
      prm.enter_subsection(subsection);
      prm.declare_entry("Sphere center", "0, 0, 0", vector_pattern, "Centre of the jaws at time 0 (m)");
      prm.declare_entry("Sphere radius", "0", Patterns::Double(0),
                        "Radius of the jaws (m): at Grasp time the free vertices within it are "
                        "grasped; 0: no grasp");
      prm.declare_entry("Velocity", "0, 0, 0", vector_pattern,
                        "Velocity (m/s) of the jaws from the grasp on, for Duration: the grasped "
                        "vertices are pulled along");
      prm.declare_entry("Duration", "0", Patterns::Double(0),
                        "How long after the grasp the jaws move (s), then hold");
      prm.declare_entry("Grasp time", "0", Patterns::Double(0), "When the jaws close (s)");
      prm.declare_entry("Release time", "inf", Patterns::Anything(),
                        "When they open and let the vertices go (s, after Grasp time), or inf: never");
      prm.declare_entry("Spring stiffness", "0", Patterns::Double(0),
                        "Stiffness (N/m) of the spring tying each grasped vertex to the jaws; 0: "
                        "a penalty spring, 1e6 times the vertex's mass over dt^2, which holds it to "
                        "the jaws within a millionth of its motion");
      declare_path_file(prm, "lines of time, x, y, z of the jaws' centre: they close around its position "
                             "at Grasp time and follow it until Release time, instead of Sphere center "
                             "and Velocity");
      prm.leave_subsection();
    }

    void Grasp::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file,
                                 const std::string &subsection)
    {
      this->subsection = subsection;
      prm.enter_subsection(subsection);
      sphere_center    = get_vector(prm, "Sphere center");
      sphere_radius    = prm.get_double("Sphere radius");
      velocity         = get_vector(prm, "Velocity");
      duration         = prm.get_double("Duration");
      grasp_time       = prm.get_double("Grasp time");
      spring_stiffness = prm.get_double("Spring stiffness");
      if (!parse_threshold(prm.get("Release time"), release_time))
        file.fail(prm, subsection, "Release time", "must be a time >= 0 (s) or inf");
      if (active() && !(release_time > grasp_time))
        file.fail(prm, subsection, "Release time", "must come after Grasp time (" + format_number(grasp_time) + " s)");
      path.file_name = parse_path_file(prm, file, subsection, velocity);
      prm.leave_subsection();
    }

    void MaterialChange::declare_parameters(ParameterHandler &prm, const std::string &subsection)
    {
      prm.enter_subsection(subsection);
      RegionParameters::declare_parameters(prm, "whose elements (all their vertices in it) change");
      prm.declare_entry("Time", "0", Patterns::Double(0), "When the material changes (s)");
      prm.declare_entry("Stiffness factor", "1", Patterns::Anything(),
                        "The Young's modulus of the region's elements is multiplied by this (> 0): "
                        "cauterized tissue stiffens (> 1), torn tissue softens (< 1)");
      prm.declare_entry("Stress", "continuous", Patterns::Selection("continuous|reset"),
                        "continuous: the changed elements keep their stress at the change (a plastic "
                        "strain takes up the rest), stiffened tissue holds its shape; reset: they keep "
                        "their rest shape, a strained element's stress is multiplied by the factor");
      prm.leave_subsection();
    }

    void MaterialChange::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file,
                                          const std::string &subsection)
    {
      this->subsection = subsection;
      prm.enter_subsection(subsection);
      region.parse_parameters(prm, file, subsection);
      time = prm.get_double("Time");
      const std::string factor = trim(prm.get("Stiffness factor"));
      char             *end    = nullptr;
      stiffness_factor         = std::strtod(factor.c_str(), &end);
      if (factor.empty() || *end != '\0' || !std::isfinite(stiffness_factor))
        file.fail(prm, subsection, "Stiffness factor", "must be a number > 0");
      if (!(stiffness_factor > 0))
        file.fail(prm, subsection, "Stiffness factor",
                  "must be > 0: a Young's modulus E <= 0 has no stiffness (a cut removes elements)");
      keep_stress = prm.get("Stress") == "continuous";
      prm.leave_subsection();
    }

    void Bodies::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Bodies");
      prm.declare_entry("Number of bodies", "1", Patterns::Integer(1, 100),
                        "Copies of the mesh simulated side by side, each with its own model and "
                        "threshold and solved on its own, in one VTU series and one log");
      prm.declare_entry("Spacing", "0, 0, 0", vector_pattern,
                        "Body i (from 0) is shown shifted by i times this vector (m); the "
                        "physics of every body is that of the scene in its own frame");
      prm.declare_entry("Models", "", Patterns::Anything(),
                        "One model type per body, comma-separated (as Model/Type); empty: "
                        "Model/Type for every body");
      prm.declare_entry("Update thresholds", "", Patterns::Anything(),
                        "One WCC update threshold per body, comma-separated (numbers >= 0 or "
                        "inf); empty: Model/Update threshold for every body");
      prm.leave_subsection();
    }

    void Bodies::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Bodies");
      count   = prm.get_integer("Number of bodies");
      spacing = get_vector(prm, "Spacing");
      model_types.clear();
      update_thresholds.clear();
      const auto items = [](const std::string &text) {
        std::vector<std::string> values;
        if (!trim(text).empty())
          for (const auto &item : dealii::Utilities::split_string_list(text, ','))
            values.push_back(trim(item));
        return values;
      };
      const auto require_one_per_body = [&](const std::string &entry, const std::size_t n) {
        if (n != 0 && n != count)
          file.fail(prm, "Bodies", entry,
                    "gives " + std::to_string(n) + " values for " + std::to_string(count) +
                      " bodies (Number of bodies)");
      };
      for (const auto &type : items(prm.get("Models")))
        {
          if (type != "linear" && type != "corotational" && type != "stiffness_warping" &&
              type != "warp_canceling")
            file.fail(prm, "Bodies", "Models",
                      quote(type) + " is not a model (linear, corotational, stiffness_warping, "
                      "warp_canceling)");
          model_types.push_back(type);
        }
      require_one_per_body("Models", model_types.size());
      for (const auto &text : items(prm.get("Update thresholds")))
        {
          double threshold = 0;
          if (!parse_threshold(text, threshold))
            file.fail(prm, "Bodies", "Update thresholds",
                      quote(text) + " is not a threshold (a number >= 0 or inf)");
          update_thresholds.push_back(threshold);
        }
      require_one_per_body("Update thresholds", update_thresholds.size());
      if (count > 1 && spacing.norm() == 0)
        file.fail(prm, "Bodies", "Spacing", "must not be zero for more than one body");
      prm.leave_subsection();
    }

    void Output::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Output");
      prm.declare_entry("Directory", "output", Patterns::Anything(),
                        "Results go to DIRECTORY/SCENE/ (relative to the working directory)");
      prm.declare_entry("Scene", "", Patterns::Anything(),
                        "The scene's name; empty: the parameter file's name without .prm");
      prm.declare_entry("VTU interval", "0", Patterns::Integer(0),
                        "Write a VTU file (and the PVD series) every this many steps, and the "
                        "initial state; 0: none");
      prm.declare_entry("VTU precision", "float32", Patterns::Selection("float32|float64"),
                        "The numbers of the VTU files: float32 (deal.II's DataOut, about 7 "
                        "digits, the smaller files) or float64 (17 digits, for comparing "
                        "trajectories with a reference beyond 1e-7; the files are about twice "
                        "as large)");
      prm.declare_entry("Write log", "false", Patterns::Bool(),
                        "Write the per-step CSV log SCENE/log.csv");
      prm.declare_entry("Print timings", "true", Patterns::Bool(),
                        "Print run times and the solver's figures (fill, columns and flops "
                        "recomputed) in the summary, with a table of the stages that ran (runs, "
                        "seconds per step, share of the run); false leaves what depends on the "
                        "model alone, the same from run to run and from solver to solver, and "
                        "lists the stages by name");
      prm.declare_entry("Progress", "auto", Patterns::Selection("auto|on|off|true|false|yes|no"),
                        "A progress line on standard error: auto shows it on a terminal; on "
                        "(or true, yes) always, off (or false, no) never");
      prm.declare_entry("Compare with corotational", "false", Patterns::Bool(),
                        "Also run the exact corotational model, in step (not timed), and report "
                        "the trajectory error max_i |x_i - x_i(corotational)| and the RMS error "
                        "sqrt(mean_i |x_i - x_i(corotational)|^2), both over "
                        "max_i |x_i(corotational) - X_i|, in the log and the summary");
      prm.declare_entry("Exact steps timed", "0", Patterns::Integer(0, 1000),
                        "After the run, time this many steps of the exact corotational model (from "
                        "rest, output off) and print what exact corotation costs a step on this "
                        "machine and the run's speed-up over it; WCC then also estimates each "
                        "step's velocity error against exact corotation (|A^-1 (b - B v)| / |v|, "
                        "B the exact matrix, A the factor's: one product and one solve a step). 0: "
                        "none");
      prm.declare_entry("Checkpoint interval", "0", Patterns::Integer(0),
                        "Write the whole state of the run (positions, velocities, the model's "
                        "matrix, stored rotations and factor, the tool, the log so far) to "
                        "SCENE/checkpoint.bin every this many steps, replacing the last one "
                        "atomically; 'warpchol FILE.prm --resume' goes on from it and gives the "
                        "same trajectory, to the bit, as a run never stopped. 0: none");
      prm.leave_subsection();
    }

    void Output::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &)
    {
      prm.enter_subsection("Output");
      directory     = prm.get("Directory");
      scene         = trim(prm.get("Scene"));
      vtu_interval  = prm.get_integer("VTU interval");
      vtu_precision = prm.get("VTU precision");
      write_log     = prm.get_bool("Write log");
      print_timings = prm.get_bool("Print timings");
      // The words of a Bool entry mean on and off, as in the other switches.
      progress = prm.get("Progress");
      if (progress == "true" || progress == "yes")
        progress = "on";
      else if (progress == "false" || progress == "no")
        progress = "off";
      compare_with_corotational = prm.get_bool("Compare with corotational");
      exact_steps_timed         = prm.get_integer("Exact steps timed");
      checkpoint_interval       = prm.get_integer("Checkpoint interval");
      prm.leave_subsection();
    }

    void Distributed::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Distributed");
      prm.declare_entry("Linear solver", "amg_cg", Patterns::Selection("amg_cg|mumps"),
                        "How a distributed run (mpirun -np N warpchol FILE.prm, or "
                        "--distributed) solves each step: amg_cg, Trilinos CG preconditioned by "
                        "ML's algebraic multigrid with the rigid-body modes, set up once on the "
                        "rest matrix and reused; mumps, the distributed direct solver MUMPS "
                        "through PETSc, factoring again whenever the matrix changed. Serial runs "
                        "ignore this subsection");
      prm.declare_entry("Tolerance", "1e-8", Patterns::Double(0),
                        "amg_cg stops at |b - A x| <= tolerance |b|");
      prm.declare_entry("Max iterations", "1000", Patterns::Integer(1),
                        "amg_cg fails the step after this many iterations");
      prm.leave_subsection();
    }

    void Distributed::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Distributed");
      linear_solver  = prm.get("Linear solver");
      tolerance      = prm.get_double("Tolerance");
      max_iterations = prm.get_integer("Max iterations");
      if (!(tolerance > 0 && tolerance < 1))
        file.fail(prm, "Distributed", "Tolerance", "must lie in (0, 1), got " + format_number(tolerance));
      prm.leave_subsection();
    }
  } // namespace parameters

  // ---------------------------------------------------------------------------------------
  void AllParameters::declare_parameters(ParameterHandler &prm)
  {
    parameters::Mesh::declare_parameters(prm);
    parameters::Material::declare_parameters(prm);
    parameters::TimeStepping::declare_parameters(prm);
    parameters::Model::declare_parameters(prm);
    parameters::Solver::declare_parameters(prm);
    parameters::InitialState::declare_parameters(prm);
    parameters::FixedVertices::declare_parameters(prm);
    parameters::Gravity::declare_parameters(prm);
    parameters::RegionForce::declare_parameters(prm);
    parameters::Tool::declare_parameters(prm);
    parameters::Cut::declare_parameters(prm);
    parameters::Grasp::declare_parameters(prm);
    parameters::MaterialChange::declare_parameters(prm);
    // The numbered events ("Cut 2", ...) are declared where a file holds them (the constructor).
    parameters::Bodies::declare_parameters(prm);
    parameters::Output::declare_parameters(prm);
    parameters::Distributed::declare_parameters(prm);
  }

  void AllParameters::parse_parameters(ParameterHandler &prm)
  {
    mesh.parse_parameters(prm, file);
    material.parse_parameters(prm, file);
    time_stepping.parse_parameters(prm, file);
    model.parse_parameters(prm, file);
    solver.parse_parameters(prm, file);
    initial_state.parse_parameters(prm, file);
    fixed_vertices.parse_parameters(prm, file);
    gravity.parse_parameters(prm, file);
    region_force.parse_parameters(prm, file);
    tool.parse_parameters(prm, file);
    cuts.assign(1, {});
    grasps.assign(1, {});
    material_changes.assign(1, {});
    cuts[0].parse_parameters(prm, file);
    grasps[0].parse_parameters(prm, file);
    material_changes[0].parse_parameters(prm, file);
    for (const auto &name : numbered_events(file.text(), "Cut"))
      cuts.emplace_back().parse_parameters(prm, file, name);
    for (const auto &name : numbered_events(file.text(), "Grasp"))
      grasps.emplace_back().parse_parameters(prm, file, name);
    for (const auto &name : numbered_events(file.text(), "Material change"))
      material_changes.emplace_back().parse_parameters(prm, file, name);
    bodies.parse_parameters(prm, file);
    output.parse_parameters(prm, file);
    distributed.parse_parameters(prm, file);
    // What one entry allows only with another: said at the entry that asks for it.
    for (unsigned int i = 0; model.target_error > 0 && i < bodies.update_thresholds.size(); ++i)
      {
        const double threshold = bodies.update_thresholds[i];
        const auto  &type      = bodies.model_types.empty() ? model.type : bodies.model_types[i];
        if (type == "warp_canceling" && (!(threshold > 0) || std::isinf(threshold)))
          {
            prm.enter_subsection("Bodies");
            file.fail(prm, "Bodies", "Update thresholds",
                      "with Model/Target error each body's threshold is where its adaptation "
                      "starts: finite and > 0 (got " + format_number(threshold) + ")");
          }
      }
    if (model.target_error > 0 && model.type == "warp_canceling" && model.strategy.iterates() &&
        model.strategy.iterate_on == fem::StepStrategy::Target::corotational)
      {
        prm.enter_subsection("Model");
        file.fail(prm, "Model", "Target error",
                  "needs a step that solves the WCC system (Strategy = partial, or Iterate on = "
                  "warp_canceling): CG on the corotational matrix is exact to the CG tolerance");
      }
    if (model.type == "warp_canceling" && model.strategy.kind == fem::StepStrategy::Kind::background &&
        model.strategy.iterate_on != fem::StepStrategy::Target::corotational)
      {
        prm.enter_subsection("Model");
        file.fail(prm, "Model", "Iterate on",
                  "must be corotational with Strategy = background: a refresh updates every element, "
                  "which makes the WCC matrix the corotational one");
      }
    check_backend(prm);
    read_paths();
    const auto strategy = model.strategy.kind;
    if ((strategy == fem::StepStrategy::Kind::delayed_top || strategy == fem::StepStrategy::Kind::automatic) &&
        solver.settings.method != cholesky::FactorizationMethod::supernodal)
      {
        prm.enter_subsection("Model");
        file.fail(prm, "Model", "Strategy",
                "refreshes the factor below the top of its tree, which needs Solver/Method = supernodal (not " +
                    cholesky::to_string(solver.settings.method) + ")");
      }
  }

  void AllParameters::check_backend(ParameterHandler &prm) const
  {
    const backends::Backend backend = solver.backend.backend;
    if (backend == backends::Backend::warpchol)
      return;
    const std::string name = backends::to_string(backend);
    const auto        fail = [&](const std::string &message) {
      prm.enter_subsection("Solver");
      file.fail(prm, "Solver", "Backend", message);
    };
    const std::vector<std::string> types = bodies.model_types.empty() ? std::vector<std::string>{model.type} :
                                                                        bodies.model_types;
    for (const std::string &type : types)
      {
        if (backend == backends::Backend::warp_preconditioned_cg && type != "corotational")
          fail("solves the exact corotational system (CG preconditioned by the rotated rest "
               "factor): needs Model/Type = corotational, not " + type);
        if (type == "warp_canceling" && model.strategy.kind != fem::StepStrategy::Kind::partial)
          fail(name + " factors in full and solves by itself: needs Model/Strategy = partial, not " +
               fem::to_string(model.strategy.kind));
        if (type == "warp_canceling" && model.target_error > 0)
          fail(name + " has no factor of warpchol's to measure a step's error with: needs "
                      "Model/Target error = 0");
      }
  }

  void AllParameters::read_paths()
  {
    const double end_of_run = time_stepping.n_steps * time_stepping.time_step;
    // A relative path is taken relative to the file that sets it, as a mesh file is.
    const auto read = [&](PathFile &path, const std::string &subsection, const unsigned int n_values,
                          const std::string &columns) {
      if (path.file_name.empty())
        return;
      const std::string name =
        path.file_name[0] == '/' ? path.file_name : file.directory_of(subsection, "Path file") + path.file_name;
      path = PathFile::read(name, n_values, columns);
    };
    read(tool.path, "Tool", 3, "time, x, y, z");
    if (!tool.path.file_name.empty() && tool.region.kind != "none")
      tool.path.check_covers(0, end_of_run, "the run (Tool/Path file)");
    for (auto &cut : cuts)
      {
        read(cut.path, cut.subsection, 6, "time, start x, y, z, end x, y, z");
        if (!cut.path.file_name.empty() && cut.duration > 0 && cut.start_time < end_of_run)
          cut.path.check_covers(cut.start_time, std::min(cut.start_time + cut.duration, end_of_run),
                                cut.subsection + " (Start time to Start time + Duration)");
      }
    for (auto &grasp : grasps)
      {
        read(grasp.path, grasp.subsection, 3, "time, x, y, z");
        if (!grasp.path.file_name.empty() && grasp.active() && grasp.grasp_time < end_of_run)
          grasp.path.check_covers(grasp.grasp_time, std::min(grasp.release_time, end_of_run),
                                  grasp.subsection + " (Grasp time to Release time)");
      }
  }

  AllParameters AllParameters::exact_corotational() const
  {
    AllParameters exact          = *this;
    exact.model.type             = "corotational";
    exact.solver.backend.backend = backends::Backend::warpchol;
    return exact;
  }

  namespace
  {
    /** Every entry of @p prm as "Subsection/Entry = value", from its short PRM form. */
    std::vector<std::string> entry_list(const ParameterHandler &prm)
    {
      std::ostringstream text;
      prm.print_parameters(text, ParameterHandler::ShortPRM);
      std::istringstream       lines(text.str());
      std::vector<std::string> path, entries;
      for (std::string line; std::getline(lines, line);)
        {
          line = trim(line);
          if (line.rfind("subsection ", 0) == 0)
            path.push_back(trim(line.substr(11)));
          else if (line == "end" && !path.empty())
            path.pop_back();
          else if (line.rfind("set ", 0) == 0)
            {
              std::string prefix;
              for (const auto &name : path)
                prefix += name + "/";
              // "set Entry    = value": the alignment is not part of it.
              const std::string assignment = line.substr(4);
              const auto        equals     = assignment.find('=');
              entries.push_back(prefix + trim(assignment.substr(0, equals)) + " = " +
                                (equals == std::string::npos ? "" : trim(assignment.substr(equals + 1))));
            }
        }
      return entries;
    }
  } // namespace

  AllParameters::AllParameters()
  {
    ParameterHandler prm;
    declare_parameters(prm);
    parse_parameters(prm);
    entries = entry_list(prm);
  }

  AllParameters::AllParameters(const std::string &filename)
  {
    check_input_file(filename, "parameter file");
    refuse_binary(filename, filename);
    file = ParameterFileLocator(filename);
    ParameterHandler prm;
    declare_parameters(prm);
    for (const auto &name : numbered_events(file.text(), "Cut"))
      parameters::Cut::declare_parameters(prm, name);
    for (const auto &name : numbered_events(file.text(), "Grasp"))
      parameters::Grasp::declare_parameters(prm, name);
    for (const auto &name : numbered_events(file.text(), "Material change"))
      parameters::MaterialChange::declare_parameters(prm, name);
    try
      {
        // deal.II reads .xml and .json files as such; a .prm file it is given as the
        // locator wrote it out, its includes in place (their paths resolved as ours).
        std::string extension = filename.substr(filename.find_last_of('.') + 1);
        std::transform(extension.begin(), extension.end(), extension.begin(),
                       [](const unsigned char c) { return std::tolower(c); });
        if (extension == "prm")
          {
            std::istringstream text(file.text());
            prm.parse_input(text, filename);
          }
        else
          prm.parse_input(filename);
      }
    catch (const dealii::ExceptionBase &error)
      {
        throw InputError(parameter_handler_message(error, file));
      }
    parse_parameters(prm);
    entries = entry_list(prm);
  }

  void AllParameters::print_defaults(std::ostream &out)
  {
    ParameterHandler prm;
    declare_parameters(prm);
    out << "# warpchol scene parameters (defaults). Run: warpchol FILE.prm\n";
    prm.print_parameters(out, ParameterHandler::PRM);
  }

  std::string AllParameters::scene_name() const
  {
    if (!output.scene.empty())
      return output.scene;
    std::string name = file.filename();
    const auto  slash = name.find_last_of('/');
    if (slash != std::string::npos)
      name = name.substr(slash + 1);
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".prm") == 0)
      name.resize(name.size() - 4);
    return name.empty() ? "scene" : name;
  }

  AllParameters AllParameters::body(const unsigned int index) const
  {
    AllParameters one = *this;
    if (!bodies.model_types.empty())
      one.model.type = bodies.model_types.at(index);
    if (!bodies.update_thresholds.empty())
      one.model.update_threshold = bodies.update_thresholds.at(index);
    one.bodies = parameters::Bodies();
    return one;
  }

  std::string AllParameters::mesh_file_path() const
  {
    if (mesh.file_name.empty() || mesh.file_name[0] == '/')
      return mesh.file_name;
    return file.directory_of("Mesh", "File") + mesh.file_name;
  }
} // namespace warpchol::app
