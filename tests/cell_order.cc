// Mesh/Cell order: SOFA's 21:1 cylinder, whose cells come in no useful order, is sorted for
// locality (its cells then meet their vertices sooner again); a generated torus, whose
// tetrahedra come 24 per hexahedron, is left as deal.II made it. Sorted or not, the body
// keeps the file's vertices and gives, vertex by vertex, the same elastic forces and the
// same solution of its implicit Euler system: only the order of the work changes.

#include "tests.h"

#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/mesh/cell_order.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/mesh/mesh_readers.h>

#include <deal.II/grid/tria.h>

#include <algorithm>
#include <array>
#include <set>

using namespace warpchol;

namespace
{
  /** What a body on the mesh gives, per vertex. */
  struct Outcome
  {
    std::vector<fem::Vector3> forces;
    std::vector<fem::Vector3> solution;
    double                    energy = 0;
  };

  /**
   * The cylinder clamped at one end, bent and twisted: the corotated forces, and the
   * solution of A x = f with A assembled in the elements' frames.
   */
  Outcome solve_on(const dealii::Triangulation<3> &triangulation, const fem::CellOrder &order)
  {
    const auto  &points = triangulation.get_vertices();
    fem::Vector3 lower  = fem::Vector3::Constant(1e300), upper = -lower;
    for (const auto &p : points)
      for (unsigned int d = 0; d < 3; ++d)
        {
          lower[d] = std::min(lower[d], p[d]);
          upper[d] = std::max(upper[d], p[d]);
        }
    unsigned int axis = 0;
    for (unsigned int d = 1; d < 3; ++d)
      if (upper[d] - lower[d] > upper[axis] - lower[axis])
        axis = d;
    const double      length = upper[axis] - lower[axis];
    std::vector<bool> fixed(points.size());
    for (unsigned int v = 0; v < points.size(); ++v)
      fixed[v] = points[v][axis] < lower[axis] + 0.05 * length;

    const fem::ElasticBody body(triangulation, fem::Material{3e4, 0.45, 1000}, fem::MassMatrix::lumped, fixed,
                                order.unknown_order);
    std::vector<fem::Vector3> positions(points.size());
    for (unsigned int v = 0; v < points.size(); ++v)
      {
        const fem::Vector3 x(points[v][0], points[v][1], points[v][2]);
        const double       s = (x[axis] - lower[axis]) / length;
        positions[v]         = x;
        positions[v][(axis + 1) % 3] += 0.2 * length * s * s;
        positions[v][(axis + 2) % 3] += 0.05 * length * s * s * s * (x[(axis + 1) % 3] - lower[(axis + 1) % 3]) /
                                        (upper[(axis + 1) % 3] - lower[(axis + 1) % 3]);
      }
    fem::ElasticBody::State state;
    body.evaluate(positions, fem::ElasticBody::Rotations::elements, state);

    const auto        coefficients = fem::SystemCoefficients::implicit_euler(0.01, 0.1, 0.01);
    fem::SystemMatrix system(body, coefficients);
    system.assemble(fem::ElementFrames::rotated(state.element_rotations));
    cholesky::SparseCholesky solver;
    solver.analyze(system.lower());
    solver.factorize(system.lower());
    std::vector<double> b(body.n_unknowns()), x;
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      if (!body.is_fixed(v))
        for (unsigned int c = 0; c < 3; ++c)
          b[body.first_unknown(v) + c] = state.forces[v][c];
    solver.solve(b, x);

    Outcome outcome;
    outcome.forces = state.forces;
    outcome.energy = state.elastic_energy;
    outcome.solution.assign(body.n_vertices(), fem::Vector3::Zero());
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      if (!body.is_fixed(v))
        for (unsigned int c = 0; c < 3; ++c)
          outcome.solution[v][c] = x[body.first_unknown(v) + c];
    return outcome;
  }

  /** max |a_v - b_v| / max |a_v| over the vertices. */
  double relative_difference(const std::vector<fem::Vector3> &a, const std::vector<fem::Vector3> &b)
  {
    double difference = 0, size = 0;
    for (std::size_t v = 0; v < a.size(); ++v)
      {
        difference = std::max(difference, (a[v] - b[v]).norm());
        size       = std::max(size, a[v].norm());
      }
    return difference / size;
  }

  /** The cells' vertex lists, each sorted (a cell by its vertices, whatever its position). */
  std::vector<std::array<unsigned int, 4>> cells_of(const dealii::Triangulation<3> &triangulation)
  {
    std::vector<std::array<unsigned int, 4>> cells;
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        std::array<unsigned int, 4> vertices;
        for (unsigned int a = 0; a < 4; ++a)
          vertices[a] = cell->vertex_index(a);
        cells.push_back(vertices);
      }
    return cells;
  }
} // namespace

int main()
{
  const std::string file = std::string(SOURCE_DIR) + "/../meshes/sofa_cylinder_pdms_12724.vtk";

  dealii::Triangulation<3> given;
  fem::read_mesh(file, given);
  const fem::CellOrder kept = fem::order_cells_for_locality(given, fem::CellOrderChoice::given);
  tests::check("given: the file's order kept, unknowns in vertex order", !kept.sorted && kept.unknown_order.empty());

  dealii::Triangulation<3> sorted;
  fem::read_mesh(file, sorted);
  const fem::CellOrder order = fem::order_cells_for_locality(sorted, fem::CellOrderChoice::automatic);
  tests::check("SOFA's cylinder, automatic: sorted", order.sorted);
  tests::check("vertices missed per cell in the file's order > 3", order.given_misses > 3);
  tests::check_below("vertices missed per cell sorted", order.sorted_misses, 1.5);

  // The same vertices at the same places, the same cells (with their orientation), permuted.
  const auto before = cells_of(given), after = cells_of(sorted);
  bool       same_cells = before.size() == after.size() && order.given_cell.size() == after.size();
  for (std::size_t e = 0; same_cells && e < after.size(); ++e)
    same_cells = after[e] == before[order.given_cell[e]];
  const std::set<unsigned int> distinct(order.given_cell.begin(), order.given_cell.end());
  tests::check("vertices kept", given.get_vertices() == sorted.get_vertices());
  tests::check("each cell its given cell's vertices, in order", same_cells);
  tests::check("the given cells a permutation", distinct.size() == after.size());
  std::vector<unsigned int> listed(order.unknown_order);
  std::sort(listed.begin(), listed.end());
  bool every_vertex_once = listed.size() == sorted.n_vertices();
  for (std::size_t v = 0; every_vertex_once && v < listed.size(); ++v)
    every_vertex_once = listed[v] == v;
  tests::check("the unknown order lists every vertex once", every_vertex_once);

  const Outcome in_file_order = solve_on(given, kept), in_sorted_order = solve_on(sorted, order);
  tests::check_below("forces per vertex, sorted against file order",
                     relative_difference(in_file_order.forces, in_sorted_order.forces), 1e-12);
  tests::check_below("elastic energy, sorted against file order",
                     std::abs(in_file_order.energy - in_sorted_order.energy) / in_file_order.energy, 1e-12);
  tests::check_below("solution of A x = f per vertex, sorted against file order",
                     relative_difference(in_file_order.solution, in_sorted_order.solution), 1e-10);

  // deal.II's tetrahedra of a hexahedral torus: 24 in a row per hexahedron, best kept.
  dealii::Triangulation<3> torus;
  fem::create_torus(torus, fem::torus_with_about(0.3, 0.1, 2000));
  const fem::CellOrder torus_order = fem::order_cells_for_locality(torus, fem::CellOrderChoice::automatic);
  tests::check("generated torus, automatic: kept", !torus_order.sorted);
  tests::check("its vertices missed per cell fewer than sorted", torus_order.given_misses < torus_order.sorted_misses);
  tests::check("locality: sorted all the same",
               fem::order_cells_for_locality(torus, fem::CellOrderChoice::locality).sorted);
}
