#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/mesh/mesh_readers.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>

#include <cmath>
#include <limits>

namespace warpchol::fem
{
  namespace
  {
    /**
     * Counts of the quadrilateral cross-section of GridGenerator::torus (a square in the
     * middle and four cells around it: 8 vertices, 12 edges, 5 cells) after @p refinements
     * uniform refinements: every edge gains a midpoint, every cell a centre.
     */
    struct CrossSectionCounts
    {
      std::size_t vertices = 8;
      std::size_t edges    = 12;
      std::size_t cells    = 5;
    };

    CrossSectionCounts cross_section(const unsigned int refinements)
    {
      CrossSectionCounts counts;
      for (unsigned int r = 0; r < refinements; ++r)
        counts = {counts.vertices + counts.edges + counts.cells,
                  2 * counts.edges + 4 * counts.cells,
                  4 * counts.cells};
      return counts;
    }

    std::size_t n_layers(const TorusGeometry &geometry)
    {
      return static_cast<std::size_t>(geometry.toroidal_cells) << geometry.refinements;
    }

    void check(const TorusGeometry &geometry)
    {
      if (!(geometry.minor_radius > 0) || !(geometry.major_radius > geometry.minor_radius))
        throw InputError("torus: the radii must satisfy 0 < minor radius < major radius, got " +
                         format_number(geometry.minor_radius) + " and " +
                         format_number(geometry.major_radius));
      if (geometry.toroidal_cells < 3)
        throw InputError("torus: at least 3 toroidal cells are needed, got " +
                         std::to_string(geometry.toroidal_cells));
    }

    /**
     * Split the (possibly refined) hexahedral mesh into tetrahedra, without manifolds. The
     * face centres the split adds are taken on the straight faces: put on a curved
     * description, they can fold tetrahedra over on a coarse mesh (the inner side of a torus
     * with 8 toroidal cells does).
     */
    void split_into_tetrahedra(dealii::Triangulation<3> &hexahedra,
                               dealii::Triangulation<3> &tetrahedra)
    {
      hexahedra.set_all_manifold_ids(dealii::numbers::flat_manifold_id);
      tetrahedra.clear();
      dealii::GridGenerator::convert_hypercube_to_simplex_mesh(hexahedra, tetrahedra);
      // The tetrahedra are the geometry: no curved description is attached to them.
      tetrahedra.set_all_manifold_ids(dealii::numbers::flat_manifold_id);
    }
  } // namespace

  std::size_t TorusGeometry::n_vertices() const
  {
    // The split into tetrahedra adds a vertex at the centre of every face of the
    // hexahedral mesh (not in the hexahedra). Every layer of hexahedra contributes the
    // cross-section's vertices, one face centre per cell of the cross-section (the faces
    // between layers) and one per edge of the cross-section (the faces along the layer).
    const CrossSectionCounts c = cross_section(refinements);
    return n_layers(*this) * (c.vertices + c.edges + c.cells);
  }

  std::size_t TorusGeometry::n_tetrahedra() const
  {
    return 24 * n_layers(*this) * cross_section(refinements).cells;
  }

  TorusGeometry torus_with_about(const double major_radius, const double minor_radius,
                                 const std::size_t target_vertices)
  {
    TorusGeometry best{major_radius, minor_radius, 3, 0};
    check(best);
    double best_stretch = std::numeric_limits<double>::infinity();
    for (unsigned int refinements = 0; refinements <= 5; ++refinements)
      {
        TorusGeometry candidate{major_radius, minor_radius, 1, refinements};
        const double  per_toroidal_cell = static_cast<double>(candidate.n_vertices());
        candidate.toroidal_cells =
          std::max(3u, static_cast<unsigned int>(std::lround(target_vertices / per_toroidal_cell)));
        const double relative_miss =
          std::abs(static_cast<double>(candidate.n_vertices()) - target_vertices) /
          static_cast<double>(target_vertices);
        if (relative_miss > 0.1)
          continue;
        // Length of a layer along the centre line against the cross-section cell size
        // (the middle square of the cross-section spans about the minor radius).
        const double layer_length =
          2 * M_PI * major_radius / static_cast<double>(n_layers(candidate));
        const double cross_section_cell = minor_radius / static_cast<double>(1u << refinements);
        const double stretch            = std::abs(std::log(layer_length / cross_section_cell));
        if (stretch < best_stretch)
          {
            best_stretch = stretch;
            best         = candidate;
          }
      }
    if (best_stretch == std::numeric_limits<double>::infinity())
      throw InputError("torus: no resolution gives about " + std::to_string(target_vertices) +
                       " vertices (at least " + std::to_string(best.n_vertices()) + ")");
    return best;
  }

  void create_torus(dealii::Triangulation<3> &triangulation, const TorusGeometry &geometry)
  {
    check(geometry);
    // Refine on the hexahedral mesh, whose manifolds (a torus on the boundary, transfinite
    // interpolation inside) place the new vertices on the curved surface.
    dealii::Triangulation<3> hexahedra;
    dealii::GridGenerator::torus(hexahedra, geometry.major_radius, geometry.minor_radius,
                                 geometry.toroidal_cells);
    hexahedra.refine_global(geometry.refinements);
    split_into_tetrahedra(hexahedra, triangulation);
  }

  namespace
  {
    /**
     * The lengths of @p n cells along an axis of length @p length, growing geometrically so
     * that the last is @p grading times the first.
     */
    std::vector<double> graded_steps(const double length, const unsigned int n, const double grading)
    {
      const double        ratio = n > 1 ? std::pow(grading, 1.0 / (n - 1)) : 1.0;
      std::vector<double> steps(n);
      double              sum = 0;
      for (unsigned int i = 0; i < n; ++i)
        sum += steps[i] = std::pow(ratio, i);
      for (double &step : steps)
        step *= length / sum;
      return steps;
    }

    /**
     * The box's hexahedra split into the 6 tetrahedra around their main diagonal (from the
     * lower to the upper corner), the grid flattened by @p flattening along (-1, 0, 1)/sqrt 2
     * about the lower corner.
     */
    TetrahedralMesh kuhn_split_box(const BoxGeometry                         &geometry,
                                   const std::array<std::vector<double>, 3> &steps)
    {
      std::array<std::vector<double>, 3> coordinates;
      for (unsigned int d = 0; d < 3; ++d)
        {
          coordinates[d].push_back(geometry.lower_corner[d]);
          for (const double step : steps[d])
            coordinates[d].push_back(coordinates[d].back() + step);
        }
      const auto         &s = geometry.subdivisions;
      TetrahedralMesh     mesh;
      mesh.name = "sliver box";
      const double n[3]   = {-M_SQRT1_2, 0, M_SQRT1_2};
      for (unsigned int k = 0; k <= s[2]; ++k)
        for (unsigned int j = 0; j <= s[1]; ++j)
          for (unsigned int i = 0; i <= s[0]; ++i)
            {
              std::array<double, 3> x{coordinates[0][i], coordinates[1][j], coordinates[2][k]};
              double                along = 0;
              for (unsigned int d = 0; d < 3; ++d)
                along += n[d] * (x[d] - geometry.lower_corner[d]);
              for (unsigned int d = 0; d < 3; ++d)
                x[d] -= (1 - geometry.sliver_flattening) * along * n[d];
              mesh.vertices.push_back(x);
            }
      const auto vertex = [&](const unsigned int i, const unsigned int j, const unsigned int k) {
        return i + (s[0] + 1) * (j + (s[1] + 1) * k);
      };
      // Kuhn's split: one tetrahedron per order in which the path from the lower corner to
      // the upper one steps along the three axes. Neighbouring hexahedra split their shared
      // faces along the same diagonal, so the mesh is conforming.
      const unsigned int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                         {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
      for (unsigned int k = 0; k < s[2]; ++k)
        for (unsigned int j = 0; j < s[1]; ++j)
          for (unsigned int i = 0; i < s[0]; ++i)
            for (const auto &order : orders)
              {
                std::array<unsigned int, 3>  corner{i, j, k};
                std::array<unsigned int, 4> tetrahedron;
                tetrahedron[0] = vertex(corner[0], corner[1], corner[2]);
                for (unsigned int a = 0; a < 3; ++a)
                  {
                    ++corner[order[a]];
                    tetrahedron[a + 1] = vertex(corner[0], corner[1], corner[2]);
                  }
                // Odd orders give negatively oriented tetrahedra: swap two vertices.
                if (order[0] + 1 != order[1] && !(order[0] == 2 && order[1] == 0))
                  std::swap(tetrahedron[2], tetrahedron[3]);
                mesh.tetrahedra.push_back(tetrahedron);
                mesh.locations.push_back("sliver box tetrahedron " +
                                         std::to_string(mesh.tetrahedra.size() - 1));
              }
      return mesh;
    }
  } // namespace

  void create_box(dealii::Triangulation<3> &triangulation, const BoxGeometry &geometry)
  {
    for (unsigned int d = 0; d < 3; ++d)
      {
        if (!(geometry.upper_corner[d] > geometry.lower_corner[d]))
          throw InputError("box: the upper corner must lie above the lower corner along every "
                           "axis (axis " + std::to_string(d) + ")");
        if (geometry.subdivisions[d] == 0)
          throw InputError("box: at least one subdivision per axis is needed (axis " +
                           std::to_string(d) + ")");
      }
    if (!(geometry.grading >= 1))
      throw InputError("box: the grading must be >= 1, got " + format_number(geometry.grading));
    if (!(geometry.sliver_flattening > 0 && geometry.sliver_flattening <= 1))
      throw InputError("box: the sliver flattening must lie in (0, 1], got " +
                       format_number(geometry.sliver_flattening));
    std::array<std::vector<double>, 3> steps;
    for (unsigned int d = 0; d < 3; ++d)
      steps[d] = graded_steps(geometry.upper_corner[d] - geometry.lower_corner[d],
                              geometry.subdivisions[d], geometry.grading);
    if (geometry.sliver_flattening < 1)
      {
        create_triangulation(kuhn_split_box(geometry, steps), triangulation);
        return;
      }
    dealii::Triangulation<3> hexahedra;
    dealii::GridGenerator::subdivided_hyper_rectangle(
      hexahedra, std::vector<std::vector<double>>(steps.begin(), steps.end()),
      geometry.lower_corner, geometry.upper_corner);
    split_into_tetrahedra(hexahedra, triangulation);
  }

  void create_cylinder(dealii::Triangulation<3> &triangulation, const CylinderGeometry &geometry)
  {
    if (!(geometry.radius > 0) || !(geometry.length > 0))
      throw InputError("cylinder: the radius and the length must be > 0, got " + format_number(geometry.radius) +
                       " and " + format_number(geometry.length));
    if (geometry.axial_cells == 0)
      throw InputError("cylinder: at least one axial cell is needed");
    // Refined on the hexahedra, whose cylindrical manifold puts new surface vertices on the
    // circle; then moved so that the rod starts at x = 0.
    dealii::Triangulation<3> hexahedra;
    dealii::GridGenerator::subdivided_cylinder(hexahedra, geometry.axial_cells, geometry.radius,
                                               geometry.length / 2);
    hexahedra.refine_global(geometry.refinements);
    dealii::GridTools::shift(dealii::Tensor<1, 3>({geometry.length / 2, 0., 0.}), hexahedra);
    split_into_tetrahedra(hexahedra, triangulation);
  }

  void create_tube(dealii::Triangulation<3> &triangulation, const TubeGeometry &geometry)
  {
    if (!(geometry.inner_radius > 0) || !(geometry.outer_radius > geometry.inner_radius) || !(geometry.length > 0))
      throw InputError("tube: need 0 < inner radius < outer radius and a length > 0, got " +
                       format_number(geometry.inner_radius) + ", " + format_number(geometry.outer_radius) +
                       " and " + format_number(geometry.length));
    if (geometry.circumferential_cells < 3 || geometry.axial_cells == 0)
      throw InputError("tube: at least 3 cells around and one along are needed");
    dealii::Triangulation<3> hexahedra;
    dealii::GridGenerator::cylinder_shell(hexahedra, geometry.length, geometry.inner_radius, geometry.outer_radius,
                                          geometry.circumferential_cells, geometry.axial_cells);
    hexahedra.refine_global(geometry.refinements);
    split_into_tetrahedra(hexahedra, triangulation);
  }
} // namespace warpchol::fem
