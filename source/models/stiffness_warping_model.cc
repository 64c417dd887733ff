#include <warpchol/models/stiffness_warping_model.h>
#include <warpchol/models/model_type.h>

namespace warpchol::fem
{
  StiffnessWarpingModel::StiffnessWarpingModel(
    const ElasticBody &body, const SystemCoefficients &coefficients,
    const cholesky::SparseCholesky::Settings &solver_settings, std::unique_ptr<backends::LinearSolver> peer)
    : ElasticityModel(body, coefficients, solver_settings, std::move(peer))
  {
    set_up_rest_system();
    solve_frame = &elastic_state.nodal_rotations;
  }

  std::string StiffnessWarpingModel::name() const
  {
    return to_string(ModelType::stiffness_warping);
  }

  void StiffnessWarpingModel::prepare_step(const std::vector<Vector3> &positions,
                                           const std::vector<Vector3> &, StepStatistics &statistics)
  {
    evaluate_elastic_state(positions, rotations_of(ModelType::stiffness_warping), statistics);
    record_no_refactorization(statistics);
    record_rerotations(false);
  }

} // namespace warpchol::fem
