// Every SIMD target this CPU runs gives the results of the baseline (scalar) kernels to
// 1e-13 relative: the batched polar decomposition, the fused element pass (forces and
// energy), the corotated product, the assembly of A (rest, rotated, warped), the update
// kernel of the factor (ranks 1 to 64: every number of columns a chunk carries on any
// target, and several chunks; a matrix whose top supernodes span several panels) and the
// solve with one right-hand side (which also agrees with BLAS's solve of two). The targets are
// forced as WARPCHOL_SIMD_TARGET forces them (simd::use_target()); the list the machine
// runs is not printed (it differs by CPU), only that the baseline is among them.

#include "bar_tests.h"
#include "modification_tests.h"
#include "tests.h"

#include <warpchol/base/simd.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/rotations.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/sparse/conversions.h>

#include <deal.II/grid/tria.h>

#include <Eigen/Geometry>

using namespace warpchol;

namespace
{
  /** What the kernels computed on one target, flattened. */
  struct Results
  {
    std::vector<double> rotations, forces, energies, product, rest, rotated, warped, factors;
    /** The solve of one right-hand side by the solver's kernel, and of two by BLAS. */
    std::vector<double> solution, blas_solutions;
    /** A right-hand side zero but on three unknowns (the forward pass skips supernodes), alone and beside b. */
    std::vector<double> sparse_solution, sparse_blas_solutions;
  };

  void append(std::vector<double> &out, const fem::Matrix3 &m)
  {
    out.insert(out.end(), m.data(), m.data() + 9);
  }

  Results compute(const fem::ElasticBody &body, const sparse::CSCMatrix &spd)
  {
    Results        results;
    tests::Random  random(11);
    // Gradients of every kind: near rotations, stretched, inverted and flat (the SVD path).
    std::vector<fem::Matrix3> gradients(203), rotations(203);
    for (std::size_t k = 0; k < gradients.size(); ++k)
      {
        for (unsigned int i = 0; i < 9; ++i)
          gradients[k].data()[i] = (k % 3 == 0 ? 0.05 : 0.6) * (2 * random.uniform() - 1);
        const fem::Vector3 axis(random.uniform(), random.uniform() - 0.5, 1);
        gradients[k] += Eigen::AngleAxisd(3 * random.uniform(), axis.normalized()).toRotationMatrix();
        if (k % 17 == 5)
          gradients[k].col(2) = -gradients[k].col(2);
        if (k % 29 == 7)
          gradients[k].col(1) = gradients[k].col(0);
      }
    fem::rotations_of(gradients.data(), rotations.data(), gradients.size());
    for (const auto &rotation : rotations)
      append(results.rotations, rotation);

    // The body deformed: a twist and a stretch.
    std::vector<fem::Vector3> positions = body.rest_positions(), velocities(body.n_vertices());
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      {
        const fem::Vector3 x = positions[v];
        positions[v]         = Eigen::AngleAxisd(0.8 * x[0], fem::Vector3::UnitX()) * x;
        positions[v][0] *= 1.1;
        velocities[v] = fem::Vector3(random.uniform(), random.uniform(), random.uniform());
      }
    fem::ElasticBody::State state;
    body.evaluate(positions, fem::ElasticBody::Rotations::elements_and_vertices, state);
    for (const auto &force : state.forces)
      results.forces.insert(results.forces.end(), force.data(), force.data() + 3);
    results.energies.push_back(state.elastic_energy);
    std::vector<fem::Vector3> product;
    fem::ElasticBody::ForceWork work;
    body.corotated_stiffness_times(&state.element_rotations, velocities, product, work);
    for (const auto &value : product)
      results.product.insert(results.product.end(), value.data(), value.data() + 3);

    // The assembly of A in each kind of frame.
    const fem::SystemCoefficients coefficients = fem::SystemCoefficients::implicit_euler(0.01, 0.1, 0.05);
    fem::SystemMatrix             system(body, coefficients);
    system.assemble(fem::ElementFrames::rest());
    results.rest = system.lower().values;
    system.assemble(fem::ElementFrames::rotated(state.element_rotations));
    results.rotated = system.lower().values;
    std::vector<std::array<fem::Matrix3, 4>> frames(body.n_elements());
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      for (unsigned int a = 0; a < 4; ++a)
        frames[e][a] = state.nodal_rotations[body.element_vertices(e)[a]].transpose() * state.element_rotations[e];
    system.assemble(fem::ElementFrames::warped(frames));
    results.warped = system.lower().values;

    // The update kernel: ranks of one chunk of columns, of several, and a downdate.
    cholesky::SparseCholesky base(tests::supernodal_metis());
    base.analyze(spd);
    base.factorize(spd);
    std::vector<double> b(2 * spd.n_cols);
    for (double &value : b)
      value = 2 * random.uniform() - 1;
    results.solution.resize(spd.n_cols);
    base.solve(b.data(), results.solution.data(), 1);
    results.blas_solutions.resize(b.size());
    base.solve(b.data(), results.blas_solutions.data(), 2);
    std::vector<double> sparse_b(b.size(), 0.);
    for (const Index k : {Index(0), spd.n_cols / 3, spd.n_cols - 1})
      sparse_b[k] = 1. + static_cast<double>(k % 7);
    std::copy(b.begin(), b.begin() + spd.n_cols, sparse_b.begin() + spd.n_cols);
    results.sparse_solution.resize(spd.n_cols);
    base.solve(sparse_b.data(), results.sparse_solution.data(), 1);
    results.sparse_blas_solutions.resize(sparse_b.size());
    base.solve(sparse_b.data(), results.sparse_blas_solutions.data(), 2);
    const sparse::CSCMatrix full = sparse::to_full_storage(spd);
    for (const Index rank : {1, 2, 3, 5, 8, 9, 12, 13, 16, 17, 33, 64})
      {
        std::vector<std::vector<Index>> rows;
        for (Index t = 0; t < rank; ++t)
          rows.push_back(tests::clique_from(full, (37 * t + 11) % spd.n_cols, 6));
        const sparse::CSCMatrix c = tests::dense_columns(spd, rows, 0.3, 100 + rank);
        cholesky::SparseCholesky solver = base;
        solver.update(c);
        const auto &updated = solver.factor().values;
        results.factors.insert(results.factors.end(), updated.begin(), updated.end());
        solver.downdate(c);
        const auto &restored = solver.factor().values;
        results.factors.insert(results.factors.end(), restored.begin(), restored.end());
      }
    return results;
  }
} // namespace

int main()
{
  dealii::Triangulation<3> triangulation;
  const std::vector<bool>  fixed =
    tests::bar_held_at_one_end(triangulation, dealii::Point<3>(1, 0.12, 0.15), {{12, 2, 3}});
  const fem::ElasticBody  body(triangulation, fem::Material{1e5, 0.45, 1000}, fem::MassMatrix::consistent, fixed);
  const sparse::CSCMatrix spd = tests::random_spd(2000, 6, 3);

  const std::vector<std::string> targets = simd::available_targets();
  tests::check("the baseline is available", !targets.empty() && targets.back() == "baseline");
  simd::use_target("baseline");
  tests::check("forced to the baseline", simd::current_target() == "baseline");
  const Results reference = compute(body, spd);

  bool all_agree = true;
  for (const std::string &target : targets)
    {
      simd::use_target(target);
      const Results results = compute(body, spd);
      const std::pair<const char *, double> differences[] = {
        {"rotations", tests::max_relative_difference(results.rotations, reference.rotations)},
        {"forces", tests::max_relative_difference(results.forces, reference.forces)},
        {"energy", tests::max_relative_difference(results.energies, reference.energies)},
        {"product", tests::max_relative_difference(results.product, reference.product)},
        {"assembly at rest", tests::max_relative_difference(results.rest, reference.rest)},
        {"assembly rotated", tests::max_relative_difference(results.rotated, reference.rotated)},
        {"assembly warped", tests::max_relative_difference(results.warped, reference.warped)},
        {"updated factors", tests::max_relative_difference(results.factors, reference.factors)},
        {"solution", tests::max_relative_difference(results.solution, reference.solution)},
        {"sparse solution", tests::max_relative_difference(results.sparse_solution, reference.sparse_solution)}};
      for (const auto &[what, difference] : differences)
        if (!(difference <= 1e-13))
          {
            all_agree = false;
            std::cout << target << ": " << what << " differs from the baseline by " << difference << std::endl;
          }
    }
  tests::check("every target agrees with the baseline to 1e-13", all_agree);
  const std::vector<double> blas_first(reference.blas_solutions.begin(),
                                       reference.blas_solutions.begin() + static_cast<long>(reference.solution.size()));
  tests::check("the solve of one right-hand side agrees with BLAS's to 1e-13",
               tests::max_relative_difference(reference.solution, blas_first) <= 1e-13);
  const std::vector<double> sparse_blas_first(reference.sparse_blas_solutions.begin(),
                                              reference.sparse_blas_solutions.begin() +
                                                static_cast<long>(reference.sparse_solution.size()));
  tests::check("so does that of a right-hand side zero but on three unknowns",
               tests::max_relative_difference(reference.sparse_solution, sparse_blas_first) <= 1e-13);

  // A target the CPU cannot run (or that does not exist) is refused, naming the available ones.
  try
    {
      simd::use_target("avx1024");
      tests::check("an unknown target is refused", false);
    }
  catch (const std::invalid_argument &error)
    {
      tests::check("an unknown target is refused", std::string(error.what()).find("baseline") != std::string::npos);
    }
  simd::use_target("best");
  tests::check("best is the first available", simd::current_target() == targets.front());
  // The default: AVX2 where the CPU has it (even with AVX-512), else the best.
  const bool has_avx2 = std::find(targets.begin(), targets.end(), "avx2") != targets.end();
  simd::use_target("default");
  tests::check("default is avx2 where available, else the best",
               simd::current_target() == (has_avx2 ? std::string("avx2") : targets.front()));
  // The update's and the assembly's default: the best; a forced target holds for them too.
  tests::check("the update's default is the best",
               simd::current_target(simd::Family::update) == targets.front());
  tests::check("the assembly's default is the best",
               simd::current_target(simd::Family::assembly) == targets.front());
  simd::use_target("baseline");
  tests::check("a forced target holds for the update",
               simd::current_target(simd::Family::update) == "baseline");
  tests::check("a forced target holds for the assembly",
               simd::current_target(simd::Family::assembly) == "baseline");
}
