// The fused element pass sums the elements' forces on their vertices as it goes, each
// thread over a range of elements: a vertex whose elements one range holds gets them added
// at once, one that two ranges share is summed after them from the kept forces. On SOFA's
// cylinder (its file's order, cells sorted for locality) and on a generated torus, bent and
// twisted, with a plastic strain on some elements: the forces, the energy and the corotated
// product are the same bits on one thread and on two (two ranges), and equal to a sum of
// each element's forces from the element's own functions (stiffness_forces()) to 1e-13.
// add_elastic_forces() adds to what the vector held.

#include "tests.h"

#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/rotations.h>
#include <warpchol/mesh/cell_order.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/mesh/mesh_readers.h>

#include <deal.II/base/multithread_info.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <cstring>

using namespace warpchol;

namespace
{
  /** What the pass gives on a number of threads. */
  struct Outcome
  {
    std::vector<fem::Vector3> forces, product, added;
    double                    energy = 0;
  };

  Outcome run_on(const fem::ElasticBody &body, const std::vector<fem::Vector3> &positions,
                 const std::vector<fem::Vector3> &velocities, const unsigned int n_threads)
  {
    dealii::MultithreadInfo::set_thread_limit(n_threads);
    Outcome                 outcome;
    fem::ElasticBody::State state;
    body.evaluate(positions, fem::ElasticBody::Rotations::elements, state);
    outcome.forces = state.forces;
    outcome.energy = state.elastic_energy;
    fem::ElasticBody::ForceWork work;
    body.corotated_stiffness_times(&state.element_rotations, velocities, outcome.product, work);
    outcome.added = velocities;
    body.add_elastic_forces(positions, &state.element_rotations, outcome.added);
    dealii::MultithreadInfo::set_thread_limit();
    return outcome;
  }

  bool same_bits(const std::vector<fem::Vector3> &a, const std::vector<fem::Vector3> &b)
  {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(fem::Vector3)) == 0;
  }

  double relative_difference(const std::vector<fem::Vector3> &a, const std::vector<fem::Vector3> &b)
  {
    double largest = 0, difference = 0;
    for (std::size_t v = 0; v < b.size(); ++v)
      {
        largest    = std::max(largest, b[v].norm());
        difference = std::max(difference, (a[v] - b[v]).norm());
      }
    return difference / largest;
  }

  void check_body(const std::string &name, const dealii::Triangulation<3> &triangulation,
                  const std::vector<unsigned int> &unknown_order)
  {
    const auto          &points = triangulation.get_vertices();
    const auto           box    = dealii::GridTools::compute_bounding_box(triangulation).get_boundary_points();
    const fem::Vector3   lower(box.first[0], box.first[1], box.first[2]);
    const fem::Vector3   upper(box.second[0], box.second[1], box.second[2]);
    std::vector<bool> fixed(points.size());
    for (unsigned int v = 0; v < points.size(); ++v)
      fixed[v] = points[v][0] < lower[0] + 0.05 * (upper[0] - lower[0]);
    fem::ElasticBody body(triangulation, fem::Material{3e4, 0.45, 1000}, fem::MassMatrix::lumped, fixed,
                          unknown_order);
    // A change that keeps the stress leaves a plastic strain on every seventh element.
    std::vector<fem::Vector3> positions(points.size()), velocities(points.size());
    const fem::Vector3        size = upper - lower;
    for (unsigned int v = 0; v < points.size(); ++v)
      {
        const fem::Vector3 x(points[v][0], points[v][1], points[v][2]);
        const fem::Vector3 s = (x - lower).cwiseQuotient(size);
        positions[v]         = x + size.cwiseProduct(fem::Vector3(0.02 * s[1], 0.1 * s[0] * s[0], 0.03 * s[0] * s[1]));
        velocities[v]        = fem::Vector3(std::sin(7 * s[0]), std::cos(5 * s[1]), s[2] - 0.5);
      }
    for (unsigned int e = 0; e < body.n_elements(); e += 7)
      body.scale_element_stiffness_keeping_stress(e, 3, body.displacement_gradient(e, positions, true));

    std::cout << name << " (" << body.n_elements() << " elements):" << std::endl;
    const Outcome one = run_on(body, positions, velocities, 1);
    const Outcome two = run_on(body, positions, velocities, 2);
    tests::check("  forces: the same bits on 1 and 2 threads", same_bits(one.forces, two.forces));
    tests::check("  energy: the same bits on 1 and 2 threads", one.energy == two.energy);
    tests::check("  corotated product: the same bits on 1 and 2 threads", same_bits(one.product, two.product));
    tests::check("  added forces: the same bits on 1 and 2 threads", same_bits(one.added, two.added));

    // The same sums from each element's own forces, one element at a time.
    std::vector<fem::Vector3> reference(points.size(), fem::Vector3::Zero());
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      {
        const fem::Matrix3 gradient = body.deformation_gradient(e, positions);
        fem::Matrix3       rotation;
        fem::rotations_of(&gradient, &rotation, 1);
        const fem::Matrix3 world = -(rotation * body.stiffness_forces(e, rotation.transpose() * gradient -
                                                                              fem::Matrix3::Identity() -
                                                                              body.plastic_strain(e)));
        const auto        &v     = body.element_vertices(e);
        for (unsigned int a = 1; a < 4; ++a)
          {
            reference[v[a]] += world.col(a - 1);
            reference[v[0]] -= world.col(a - 1);
          }
      }
    tests::check_below("  forces against each element's own", relative_difference(one.forces, reference), 1e-13);
    std::vector<fem::Vector3> added = velocities;
    for (unsigned int v = 0; v < points.size(); ++v)
      added[v] += one.forces[v];
    tests::check_below("  added forces against velocities + forces", relative_difference(one.added, added), 1e-13);
  }
} // namespace

int main()
{
  dealii::Triangulation<3> cylinder;
  fem::read_mesh(std::string(SOURCE_DIR) + "/../meshes/sofa_cylinder_pdms_12724.vtk", cylinder);
  const fem::CellOrder cylinder_order = fem::order_cells_for_locality(cylinder, fem::CellOrderChoice::automatic);
  check_body("SOFA's cylinder, sorted", cylinder, cylinder_order.unknown_order);

  dealii::Triangulation<3> torus;
  fem::create_torus(torus, fem::torus_with_about(0.3, 0.1, 8000));
  const fem::CellOrder torus_order = fem::order_cells_for_locality(torus, fem::CellOrderChoice::automatic);
  check_body("generated torus", torus, torus_order.unknown_order);
}
