#pragma once

#include <deal.II/base/point.h>
#include <deal.II/grid/tria.h>

#include <array>
#include <cstddef>

/**
 * @file
 * Generated tetrahedral meshes: deal.II builds a hexahedral mesh (GridGenerator), refines
 * it on its curved description, and splits every hexahedron into 24 tetrahedra
 * (GridGenerator::convert_hypercube_to_simplex_mesh). The result carries no manifold: the
 * simulation works on the straight-sided tetrahedra it was given.
 */
namespace warpchol::fem
{
  /**
   * A solid torus around the y axis (deal.II's GridGenerator::torus): its centre line is the
   * circle of radius @p major_radius in the x-z plane, its cross-section a disk of radius
   * @p minor_radius.
   */
  struct TorusGeometry
  {
    double       major_radius = 0.3;
    double       minor_radius = 0.1;
    /** Hexahedral layers around the centre line before refinement (at least 3). */
    unsigned int toroidal_cells = 6;
    /** Global refinements of the hexahedral mesh before the split into tetrahedra. */
    unsigned int refinements = 0;

    /** Vertices of the tetrahedral mesh create_torus() makes (a closed formula). */
    std::size_t n_vertices() const;
    /** Tetrahedra of the tetrahedral mesh create_torus() makes. */
    std::size_t n_tetrahedra() const;
  };

  /**
   * The torus resolution whose mesh has about @p target_vertices vertices, with elements as
   * little stretched along the centre line as the counts allow: among the refinement levels,
   * take the one whose layer count (chosen to hit the target) gives layers closest to the
   * cross-section's cell size.
   */
  TorusGeometry torus_with_about(double major_radius, double minor_radius,
                                 std::size_t target_vertices);

  /** Fill @p triangulation (cleared first) with the tetrahedral torus of @p geometry. */
  void create_torus(dealii::Triangulation<3> &triangulation, const TorusGeometry &geometry);

  /**
   * An axis-aligned box split into subdivisions[d] hexahedra along axis d, and two ways to
   * spoil it on purpose (the meshes of the stability tests):
   * - @p grading > 1: the hexahedra grow geometrically along every axis, the last one
   *   @p grading times as long as the first: element sizes span a factor @p grading;
   * - @p sliver_flattening < 1: every hexahedron is split into the 6 tetrahedra around its
   *   main diagonal (Kuhn's split) instead of 24, and the box is flattened along
   *   (-1, 0, 1) / sqrt 2 by this factor. No edge of those tetrahedra is parallel to that
   *   direction, so they flatten without a short edge: slivers (four nearly coplanar
   *   vertices, dihedral angles near 0 and 180 degrees) whose volume is this fraction of
   *   the unflattened one, on cubic hexahedra. The body becomes a parallelepiped.
   */
  struct BoxGeometry
  {
    dealii::Point<3>            lower_corner{0, 0, 0};
    dealii::Point<3>            upper_corner{1, 1, 1};
    std::array<unsigned int, 3> subdivisions{{1, 1, 1}};
    double                      grading           = 1;
    double                      sliver_flattening = 1;
  };

  /** Fill @p triangulation (cleared first) with the tetrahedral box of @p geometry. */
  void create_box(dealii::Triangulation<3> &triangulation, const BoxGeometry &geometry);

  /**
   * A solid circular cylinder along the x axis from x = 0 to x = @p length (deal.II's
   * GridGenerator::subdivided_cylinder: a cross-section of 5 hexahedra, @p axial_cells
   * layers), refined @p refinements times on its curved surface: a slender rod or beam.
   */
  struct CylinderGeometry
  {
    double       radius       = 0.025;
    double       length       = 1;
    unsigned int axial_cells  = 20;
    unsigned int refinements  = 1;
  };

  /** Fill @p triangulation (cleared first) with the tetrahedral cylinder of @p geometry. */
  void create_cylinder(dealii::Triangulation<3> &triangulation, const CylinderGeometry &geometry);

  /**
   * A tube along the z axis from z = 0 to z = @p length, the space between two coaxial
   * cylinders (deal.II's GridGenerator::cylinder_shell: one layer of hexahedra through the
   * wall, @p circumferential_cells around it, @p axial_cells along it), refined
   * @p refinements times: a vessel.
   */
  struct TubeGeometry
  {
    double       inner_radius         = 0.004;
    double       outer_radius         = 0.005;
    double       length               = 0.1;
    unsigned int circumferential_cells = 12;
    unsigned int axial_cells          = 20;
    unsigned int refinements          = 0;
  };

  /** Fill @p triangulation (cleared first) with the tetrahedral tube of @p geometry. */
  void create_tube(dealii::Triangulation<3> &triangulation, const TubeGeometry &geometry);
} // namespace warpchol::fem
