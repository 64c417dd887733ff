#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/fem/elasticity_model.h>

#include <algorithm>

namespace warpchol::fem
{
  ElasticityModel::ElasticityModel(const ElasticBody &body, const SystemCoefficients &coefficients,
                                   const cholesky::SparseCholesky::Settings &solver_settings)
    : body(body)
    , coefficients(coefficients)
    , system(body, coefficients)
    , cholesky_solver(solver_settings)
  {
    if (body.n_unknowns() == 0)
      throw InputError("every vertex is fixed: nothing to simulate");
    record.updated.assign(body.n_elements(), 0);
    record.steps_since_update.assign(body.n_elements(), 0);
  }

  bool ElasticityModel::uses_rotations() const
  {
    return true;
  }

  template <typename Factor>
  void ElasticityModel::checked(const Factor &factor)
  {
    try
      {
        factor();
      }
    catch (const NotPositiveDefinite &failure)
      {
        const unsigned int vertex = body.vertex_of_unknown(failure.column);
        throw MatrixError("the Cholesky factorization failed at column " +
                          std::to_string(failure.column) + " (vertex " + std::to_string(vertex) +
                          ", component " + "xyz"[failure.column % 3] +
                          "): pivot " + format_number(failure.pivot) +
                          ", the system matrix is not positive definite");
      }
  }

  void ElasticityModel::set_up_rest_system()
  {
    Stopwatch stopwatch;
    system.assemble([&](const unsigned int e, ElementMatrix &matrix) {
      matrix = rest_element_matrix(body, e, coefficients);
    });
    StepStatistics setup;
    factorize(setup);
    setup_time = stopwatch.seconds();
  }

  void ElasticityModel::factorize(StepStatistics &statistics)
  {
    Stopwatch stopwatch;
    checked([&]() {
      if (cholesky_solver.statistics().n == 0)
        cholesky_solver.analyze(system.csc());
      cholesky_solver.factorize(system.csc());
    });
    record_refactorization(statistics);
    statistics.t_factor += stopwatch.seconds();
  }

  void ElasticityModel::refactorize(const std::vector<Index> &changed_columns,
                                    StepStatistics           &statistics)
  {
    Stopwatch stopwatch;
    checked([&]() { cholesky_solver.refactorize(system.csc(), changed_columns); });
    record_refactorization(statistics);
    statistics.t_factor += stopwatch.seconds();
  }

  void ElasticityModel::record_refactorization(StepStatistics &statistics) const
  {
    // After a full factorization the solver reports every column and the full flops.
    const auto &solver_statistics = cholesky_solver.statistics();
    statistics.refactorized       = true;
    statistics.columns_recomputed = solver_statistics.columns_recomputed;
    statistics.flops_recomputed   = solver_statistics.flops_recomputed;
    record_no_refactorization(statistics);
  }

  void ElasticityModel::record_no_refactorization(StepStatistics &statistics) const
  {
    statistics.n_columns  = body.n_unknowns();
    statistics.flops_full = cholesky_solver.statistics().method_flops;
  }

  void ElasticityModel::solve(const std::vector<Vector3> &right_hand_side,
                              std::vector<Vector3> &velocities, StepStatistics &statistics) const
  {
    Stopwatch stopwatch;
    // A y = R^T rhs, then v = R y: the nodal rotations stand for the updates A lacks.
    std::vector<double> rotated(body.n_unknowns());
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      {
        const Index first = body.first_unknown(v);
        if (first < 0)
          continue;
        const Vector3 local =
          solve_frame ? Vector3((*solve_frame)[v].transpose() * right_hand_side[v]) : right_hand_side[v];
        for (unsigned int c = 0; c < 3; ++c)
          rotated[first + c] = local[c];
      }
    std::vector<double> solution(body.n_unknowns());
    cholesky_solver.solve(rotated, solution);
    velocities.resize(body.n_vertices());
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      {
        const Index first = body.first_unknown(v);
        if (first < 0)
          {
            velocities[v].setZero();
            continue;
          }
        const Vector3 local(solution[first], solution[first + 1], solution[first + 2]);
        velocities[v] = solve_frame ? Vector3((*solve_frame)[v] * local) : local;
      }
    statistics.t_solve += stopwatch.seconds();
  }

  void ElasticityModel::record_updates(const std::vector<unsigned int> &updated)
  {
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      {
        record.updated[e] = 0;
        ++record.steps_since_update[e];
      }
    for (const unsigned int e : updated)
      {
        record.updated[e]            = 1;
        record.steps_since_update[e] = 0;
      }
  }

  void ElasticityModel::record_updates(const bool all)
  {
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      {
        record.updated[e]            = all ? 1 : 0;
        record.steps_since_update[e] = all ? 0 : record.steps_since_update[e] + 1;
      }
  }

  const ElementUpdateRecord &ElasticityModel::update_record() const
  {
    return record;
  }

  const SystemMatrix &ElasticityModel::system_matrix() const
  {
    return system;
  }

  const cholesky::SparseCholesky &ElasticityModel::solver() const
  {
    return cholesky_solver;
  }

  double ElasticityModel::setup_seconds() const
  {
    return setup_time;
  }
} // namespace warpchol::fem
