#pragma once

#include <warpchol/models/elasticity_model.h>

/**
 * @file
 * Exact corotation (Mueller and Gross 2004).
 */
namespace warpchol::fem
{
  /**
   * The corotational model: every step, the rotation R_e of every element (polar
   * decomposition), A assembled from R_e K_e R_e^T and factored anew. The reference the
   * cheaper models are measured against.
   */
  class CorotationalModel : public ElasticityModel
  {
  public:
    CorotationalModel(const ElasticBody &body, const SystemCoefficients &coefficients,
                      const cholesky::SparseCholesky::Settings &solver_settings,
                      std::unique_ptr<backends::LinearSolver> peer = nullptr);

    std::string name() const override;

    void prepare_step(const std::vector<Vector3> &positions, const std::vector<Vector3> &velocities,
                      StepStatistics &statistics) override;

  protected:
    /** R_e K_e R_e^T: every element in its own rotation of the last step. */
    ElementFrames contribution_frames() const override;
    /** Every step assembles and factors A in full. */
    bool assembles_every_step() const override;

  };
} // namespace warpchol::fem
