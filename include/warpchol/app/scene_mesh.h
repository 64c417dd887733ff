#pragma once

#include <warpchol/app/parameters.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/mesh/cell_order.h>
#include <warpchol/mesh/mesh_readers.h>

#include <deal.II/grid/tria.h>

#include <string>
#include <vector>

/**
 * @file
 * The mesh of a scene and its regions, as the parameters describe them: what a serial
 * Scene and a distributed run (distributed/) both start from.
 */
namespace warpchol::app
{
  /**
   * The whole mesh of a scene (Mesh subsection: a generated torus or box, or a mesh file,
   * scaled), in a serial Triangulation<3>, with the file's vertex numbering, and the
   * vertices its regions (fixed vertices, region force, tool) select.
   */
  class SceneMesh
  {
  public:
    /** Build the mesh; throws InputError naming the parameter or the mesh file. */
    explicit SceneMesh(const AllParameters &parameters);

    const dealii::Triangulation<3> &triangulation() const;
    /**
     * The order of the cells and the unknowns (Mesh/Cell order): each cell's index in the
     * file's (or the generator's) order, the order of the unknowns.
     */
    const fem::CellOrder &cell_order() const;
    /** "generated torus (R 0.3, r 0.1, 16 toroidal cells, 1 refinements)" or the mesh file's name. */
    const std::string &description() const;

    /**
     * The vertices of a region (sorted): in a box or sphere of rest positions, or by ids in
     * the mesh file's numbering. Throws InputError naming @p subsection's entries when the
     * region selects nothing or an id does not exist.
     */
    std::vector<unsigned int> select_vertices(const RegionParameters &region,
                                              const std::string      &subsection) const;

    /**
     * Partition the cells into @p n_parts parts with METIS (their subdomain ids), for a
     * distributed run: the same partition on every rank that calls it.
     */
    void partition(unsigned int n_parts);

    /** Per vertex of the mesh, whether @p vertices (of select_vertices()) holds it. */
    std::vector<bool> marks(const std::vector<unsigned int> &vertices) const;

    /** The volume of the tetrahedra, from their vertices. */
    double volume() const;

    /**
     * The Material subsection's material; with a Total mass, the density that gives the
     * mesh that mass.
     */
    fem::Material material() const;

  private:
    const AllParameters     &all;
    dealii::Triangulation<3> tria;
    fem::MeshFileNumbering   numbering;
    fem::CellOrder           order;
    std::string              text;
  };
} // namespace warpchol::app
