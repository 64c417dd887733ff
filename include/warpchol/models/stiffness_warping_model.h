#pragma once

#include <warpchol/models/elasticity_model.h>

/**
 * @file
 * Stiffness warping (Mueller, Dorsey, McMillan, Jagnow and Cutler 2002).
 */
namespace warpchol::fem
{
  /**
   * The stiffness warping model: the rest matrix A0, factored once, is warped by the nodal
   * rotations R (volume-weighted averages of the element rotations): the step solves
   * R A0 R^T v = rhs as A0 y = R^T rhs, v = R y. The elastic forces on the right-hand side
   * are the exact corotated ones (per-element rotations), as in WCC, so that WCC with no
   * update at all is exactly this model.
   */
  class StiffnessWarpingModel : public ElasticityModel
  {
  public:
    StiffnessWarpingModel(const ElasticBody &body, const SystemCoefficients &coefficients,
                          const cholesky::SparseCholesky::Settings &solver_settings,
                          std::unique_ptr<backends::LinearSolver> peer = nullptr);

    std::string name() const override;

    void prepare_step(const std::vector<Vector3> &positions, const std::vector<Vector3> &velocities,
                      StepStatistics &statistics) override;


  };
} // namespace warpchol::fem
