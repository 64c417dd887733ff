#include <warpchol/app/parameters/entries.h>

#include <deal.II/base/utilities.h>

#include <cmath>
#include <limits>

namespace warpchol::app
{
  namespace parameters
  {
    Patterns::List vector_pattern()
    {
      return Patterns::List(Patterns::Double(), 3, 3, ",");
    }

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

    void declare_path_file(ParameterHandler &prm, const std::string &effect)
    {
      prm.declare_entry("Path file", "", Patterns::Anything(),
                        "A recorded path (CSV, relative to this file; empty: none), linear between its "
                        "samples: " + effect);
    }

    std::string parse_path_file(ParameterHandler &prm, const ParameterFileLocator &file,
                                const std::string &subsection, const fem::Vector3 &velocity)
    {
      const std::string name = trim(prm.get("Path file"));
      if (!name.empty() && velocity.norm() > 0)
        file.fail(prm, subsection, "Velocity", "must be 0 with a Path file: the path moves the instrument");
      return name;
    }
  } // namespace parameters

  using parameters::get_vector;
  using parameters::ParameterHandler;
  using parameters::require_positive;
  using parameters::trim;
  using parameters::vector_pattern;
  namespace Patterns = parameters::Patterns;

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
    prm.declare_entry("Box lower corner", "0, 0, 0", vector_pattern(),
                      "Region = box: the corner with the smallest coordinates (m)");
    prm.declare_entry("Box upper corner", "0, 0, 0", vector_pattern(),
                      "Region = box: the corner with the largest coordinates (m)");
    prm.declare_entry("Sphere center", "0, 0, 0", vector_pattern(),
                      "Region = sphere: the centre (m)");
    prm.declare_entry("Sphere radius", "0", Patterns::Double(0),
                      "Region = sphere: the radius (m)");
    prm.declare_entry("Vertex ids", "", Patterns::List(Patterns::Integer(0), 0, Patterns::List::max_int_value, ","),
                      "Region = ids: vertex ids counted from 0 in the order of the mesh "
                      "file's node list (SOFA's numbering), or of a generated mesh's vertices; "
                      "given without a Region, the region is these ids");
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
    // Ids written without a Region mean those vertices: the default (none) would drop them.
    if (!vertex_ids.empty() && !file.sets(subsection, "Region"))
      kind = "ids";
    if (kind == "box" && !(box_upper_corner.array() >= box_lower_corner.array()).all())
      file.fail(prm, subsection, "Box upper corner",
                "must not lie below Box lower corner along any axis");
    if (kind == "sphere")
      require_positive(prm, file, subsection, "Sphere radius");
    if (kind == "ids" && vertex_ids.empty())
      file.fail(prm, subsection, "Vertex ids", "Region = ids needs at least one id");
  }
} // namespace warpchol::app
