#include <warpchol/base/stopwatch.h>
#include <warpchol/fem/stiffness_warping_model.h>

namespace warpchol::fem
{
  StiffnessWarpingModel::StiffnessWarpingModel(
    const ElasticBody &body, const SystemCoefficients &coefficients,
    const cholesky::SparseCholesky::Settings &solver_settings)
    : ElasticityModel(body, coefficients, solver_settings)
  {
    set_up_rest_system();
    solve_frame = &nodal_rotations;
  }

  std::string StiffnessWarpingModel::name() const
  {
    return "stiffness_warping";
  }

  void StiffnessWarpingModel::prepare_step(const std::vector<Vector3> &positions,
                                           const std::vector<Vector3> &, StepStatistics &statistics)
  {
    Stopwatch stopwatch;
    body.compute_element_rotations(positions, element_rotations);
    body.compute_nodal_rotations(element_rotations, nodal_rotations);
    statistics.t_rotations += stopwatch.seconds();
    record_no_refactorization(statistics);
    record_updates(false);
  }

  void StiffnessWarpingModel::add_elastic_forces(const std::vector<Vector3> &positions,
                                                 std::vector<Vector3>       &forces) const
  {
    body.add_elastic_forces(positions, &element_rotations, forces);
  }
} // namespace warpchol::fem
