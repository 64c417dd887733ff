// The fast assembly of A (SystemMatrix from ElementFrames: the blocks formed from the shape
// function gradients, eight elements per SIMD lane group, columns owned by threads) equals
// the reference one (the dense 12x12 warped_element_matrix() with the stored K_e, scattered
// element by element) to 1e-14 relative, at rest, rotated and warped, with the lumped and
// the consistent mass and a tool's vertex diagonal; a partial re-assembly gives the very
// bits of a full assembly with the same frames (so that a partial refactorization sees only
// the columns that changed); one thread and two give the same bits.

#include "bar_tests.h"
#include "tests.h"

#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/mesh/mesh_generators.h>

#include <deal.II/base/multithread_info.h>
#include <deal.II/grid/tria.h>

#include <Eigen/Geometry>

#include <array>

namespace
{
  using namespace warpchol;

  fem::Matrix3 random_rotation(tests::Random &random, const double largest_angle)
  {
    const fem::Vector3 axis(2 * random.uniform() - 1, 2 * random.uniform() - 1, 2 * random.uniform() - 1);
    return Eigen::AngleAxisd(largest_angle * random.uniform(), axis.normalized()).toRotationMatrix();
  }

  /** max |A - B| / max |B| over the stored entries (the same pattern). */
  double relative_difference(const sparse::CSCMatrix &a, const sparse::CSCMatrix &b)
  {
    double largest = 0, difference = 0;
    for (std::size_t k = 0; k < b.values.size(); ++k)
      {
        largest    = std::max(largest, std::abs(b.values[k]));
        difference = std::max(difference, std::abs(a.values[k] - b.values[k]));
      }
    return difference / largest;
  }

  // The comparisons of one mass matrix in the order of the .output file: a list, kept in one place.
  void run(const fem::MassMatrix mass, const std::string &label)
  {
    std::cout << label << " mass:" << std::endl;
    // Fixed vertices at one end, and vertices numbered so that blocks land both ways.
    dealii::Triangulation<3> triangulation;
    const std::vector<bool>  fixed =
      tests::bar_held_at_one_end(triangulation, dealii::Point<3>(1, 0.1, 0.15), {{10, 2, 3}});
    const fem::ElasticBody body(triangulation, fem::Material{1e5, 0.45, 1000}, mass, fixed);
    fem::SystemCoefficients coefficients = fem::SystemCoefficients::implicit_euler(0.01, 0.1, 0.05);
    coefficients.vertex_diagonal.assign(body.n_vertices(), 0.);
    for (unsigned int v = 0; v < body.n_vertices(); v += 7)
      coefficients.vertex_diagonal[v] = 3.5;

    tests::Random                            random(5);
    std::vector<fem::Matrix3>                element_rotations(body.n_elements());
    std::vector<std::array<fem::Matrix3, 4>> frames(body.n_elements());
    std::vector<fem::Matrix3>                nodal(body.n_vertices());
    for (auto &rotation : nodal)
      rotation = random_rotation(random, 3);
    const auto set_frames = [&](const unsigned int e) {
      element_rotations[e] = random_rotation(random, 3);
      for (unsigned int a = 0; a < 4; ++a)
        frames[e][a] = nodal[body.element_vertices(e)[a]].transpose() * element_rotations[e];
    };
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      set_frames(e);
    const auto reference_warped = [&](const unsigned int e, fem::ElementMatrix &m) {
      std::array<fem::Matrix3, 4> vertex_rotations;
      for (unsigned int a = 0; a < 4; ++a)
        vertex_rotations[a] = nodal[body.element_vertices(e)[a]];
      m = fem::warped_element_matrix(body, e, coefficients, vertex_rotations, element_rotations[e]);
    };
    std::array<fem::Matrix3, 4> identity;
    identity.fill(fem::Matrix3::Identity());

    fem::SystemMatrix fast(body, coefficients), reference(body, coefficients);
    fast.assemble(fem::ElementFrames::rest());
    reference.assemble([&](const unsigned int e, fem::ElementMatrix &m) { m = fem::rest_element_matrix(body, e, coefficients); });
    tests::check_below("  at rest, relative difference", relative_difference(fast.lower(), reference.lower()), 1e-14);

    fast.assemble(fem::ElementFrames::rotated(element_rotations));
    reference.assemble([&](const unsigned int e, fem::ElementMatrix &m) {
      m = fem::warped_element_matrix(body, e, coefficients, identity, element_rotations[e]);
    });
    tests::check_below("  rotated, relative difference", relative_difference(fast.lower(), reference.lower()), 1e-14);

    fast.assemble(fem::ElementFrames::warped(frames));
    reference.assemble(reference_warped);
    tests::check_below("  warped, relative difference", relative_difference(fast.lower(), reference.lower()), 1e-14);

    // Partial re-assembly: a few elements, then enough that it assembles all of A.
    fem::SystemMatrix full(body, coefficients);
    for (const unsigned int every : {97u, 3u})
      {
        std::vector<unsigned int> changed;
        for (unsigned int e = every / 2; e < body.n_elements(); e += every)
          {
            set_frames(e);
            changed.push_back(e);
          }
        const std::vector<Index> columns = fast.reassemble(changed, fem::ElementFrames::warped(frames));
        const std::vector<Index> reference_columns = reference.reassemble(changed, reference_warped);
        full.assemble(fem::ElementFrames::warped(frames));
        std::cout << "  every " << every << "th element re-assembled:" << std::endl;
        tests::check_below("    relative difference to the reference", relative_difference(fast.lower(), reference.lower()),
                           1e-14);
        tests::check("    the same bits as a full assembly", fast.lower().values == full.lower().values);
        tests::check("    the same changed columns as the reference", columns == reference_columns);
        // The columns that changed are those of the elements' free vertices, no others.
        std::vector<char> is_changed(body.n_unknowns(), 0);
        for (const Index j : columns)
          is_changed[j] = 1;
        bool only_those = !columns.empty();
        for (const unsigned int e : changed)
          for (const unsigned int v : body.element_vertices(e))
            if (!body.is_fixed(v))
              only_those = only_those && is_changed[body.first_unknown(v)];
        tests::check("    the changed columns are the free dofs of the elements", only_those);
      }

    // Threads own ranges of columns: the same bits with one and two.
    dealii::MultithreadInfo::set_thread_limit(1);
    fem::SystemMatrix one_thread(body, coefficients);
    one_thread.assemble(fem::ElementFrames::warped(frames));
    dealii::MultithreadInfo::set_thread_limit(2);
    fem::SystemMatrix two_threads(body, coefficients);
    two_threads.assemble(fem::ElementFrames::warped(frames));
    tests::check("  one and two threads give the same bits", one_thread.lower().values == two_threads.lower().values);

    // The full CSC and deal.II forms made from the lower triangle.
    const sparse::CSCMatrix &full_csc = fast.csc();
    double                   largest_asymmetry = 0;
    for (Index j = 0; j < full_csc.n_cols; ++j)
      for (Index k = full_csc.column_start[j]; k < full_csc.column_start[j + 1]; ++k)
        largest_asymmetry = std::max(largest_asymmetry,
                                     std::abs(full_csc.values[k] - full_csc(j, full_csc.row_index[k])));
    tests::check("  the full form is symmetric and holds the lower triangle",
                 largest_asymmetry == 0 && full_csc(5, 2) == fast.lower()(5, 2));
    const auto &dealii_form = fast.matrix();
    tests::check("  the deal.II form holds the same entries",
                 dealii_form.n_nonzero_elements() == static_cast<std::size_t>(full_csc.n_nonzeros()) &&
                   dealii_form.el(7, 2) == full_csc(7, 2) && dealii_form.el(2, 7) == full_csc(2, 7));
  }
} // namespace

int main()
{
  run(fem::MassMatrix::lumped, "lumped");
  run(fem::MassMatrix::consistent, "consistent");
}
