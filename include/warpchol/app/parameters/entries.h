#pragma once

#include <warpchol/app/parameters/parameter_file.h>
#include <warpchol/fem/small_dense.h>

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <vector>

/**
 * @file
 * The entries that several subsections of a parameter file declare and parse alike: a
 * threshold, a region of vertices, a vector, a path file.
 */
namespace warpchol::app
{
  /**
   * A WCC re-rotation threshold as a parameter file or a command line writes it: a number >= 0
   * or inf (infinity). Returns false (and leaves @p threshold unspecified) for anything else.
   */
  bool parse_threshold(const std::string &text, double &threshold);

  /** A set of vertices given by a region: a box, a sphere, a list of ids, all or none. */
  struct RegionParameters
  {
    std::string         kind = "none";
    fem::Vector3        box_lower_corner{0, 0, 0};
    fem::Vector3        box_upper_corner{0, 0, 0};
    fem::Vector3        sphere_center{0, 0, 0};
    double              sphere_radius = 0;
    std::vector<long>   vertex_ids;

    /** The region entries, in the current subsection; @p what says what the region is for. */
    static void declare_parameters(dealii::ParameterHandler &prm, const std::string &what,
                                   const std::string &default_kind = "none");
    void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file,
                                 const std::string &subsection);
  };

  namespace parameters
  {
    /** The pattern of a vector entry: three numbers, comma-separated. */
    dealii::Patterns::List vector_pattern();

    /** The vector entry @p entry of the current subsection. */
    fem::Vector3 get_vector(dealii::ParameterHandler &prm, const std::string &entry);

    /** Fail at Subsection/Entry unless the entry's number is > 0. */
    void require_positive(dealii::ParameterHandler &prm, const ParameterFileLocator &file,
                          const std::string &subsection, const std::string &entry);

    /** The entry "Path file" of an instrument, in the current subsection; @p effect: what it does. */
    void declare_path_file(dealii::ParameterHandler &prm, const std::string &effect);

    /** The entry "Path file" (trimmed); with one, the instrument must not also move with @p velocity. */
    std::string parse_path_file(dealii::ParameterHandler &prm, const ParameterFileLocator &file,
                                const std::string &subsection, const fem::Vector3 &velocity);
  } // namespace parameters
} // namespace warpchol::app
