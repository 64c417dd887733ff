#include <warpchol/models/corotational_model.h>
#include <warpchol/models/model_type.h>

namespace warpchol::fem
{
  CorotationalModel::CorotationalModel(const ElasticBody &body,
                                       const SystemCoefficients &coefficients,
                                       const cholesky::SparseCholesky::Settings &solver_settings,
                                       std::unique_ptr<backends::LinearSolver>   peer)
    : ElasticityModel(body, coefficients, solver_settings, std::move(peer))
  {
    // Ordering and symbolic analysis once (the pattern never changes); the numeric factor
    // of the rest matrix is replaced in the first step.
    set_up_rest_system();
  }

  std::string CorotationalModel::name() const
  {
    return to_string(ModelType::corotational);
  }

  void CorotationalModel::prepare_step(const std::vector<Vector3> &positions,
                                       const std::vector<Vector3> &, StepStatistics &statistics)
  {
    corotational_exact_step(positions, statistics);
  }

  ElementFrames CorotationalModel::contribution_frames() const
  {
    return elastic_state.element_rotations.empty() ? ElementFrames::rest() :
                                                     ElementFrames::rotated(elastic_state.element_rotations);
  }

  bool CorotationalModel::assembles_every_step() const
  {
    return true;
  }
} // namespace warpchol::fem
