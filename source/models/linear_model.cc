#include <warpchol/models/linear_model.h>
#include <warpchol/models/model_type.h>

namespace warpchol::fem
{
  LinearModel::LinearModel(const ElasticBody &body, const SystemCoefficients &coefficients,
                           const cholesky::SparseCholesky::Settings &solver_settings,
                           std::unique_ptr<backends::LinearSolver>   peer)
    : ElasticityModel(body, coefficients, solver_settings, std::move(peer))
  {
    set_up_rest_system();
  }

  std::string LinearModel::name() const
  {
    return to_string(ModelType::linear);
  }

  bool LinearModel::uses_rotations() const
  {
    return false;
  }

  void LinearModel::prepare_step(const std::vector<Vector3> &positions, const std::vector<Vector3> &,
                                 StepStatistics &statistics)
  {
    evaluate_elastic_state(positions, rotations_of(ModelType::linear), statistics);
    record_rerotations(false);
    record_no_refactorization(statistics);
  }

} // namespace warpchol::fem
