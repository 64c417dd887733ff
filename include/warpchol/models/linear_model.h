#pragma once

#include <warpchol/models/elasticity_model.h>

/**
 * @file
 * Linear elasticity: small displacements, no rotation at all.
 */
namespace warpchol::fem
{
  /**
   * The linear model: A = c_M M + c_K K is the rest matrix, factored once; the elastic
   * forces are -K (x - X). Large rotations show its flaw: a rotated body grows.
   */
  class LinearModel : public ElasticityModel
  {
  public:
    LinearModel(const ElasticBody &body, const SystemCoefficients &coefficients,
                const cholesky::SparseCholesky::Settings &solver_settings,
                std::unique_ptr<backends::LinearSolver> peer = nullptr);

    std::string name() const override;
    bool        uses_rotations() const override;

    /** A never changes: only the elastic forces are evaluated. */
    void prepare_step(const std::vector<Vector3> &positions, const std::vector<Vector3> &velocities,
                      StepStatistics &statistics) override;

  };
} // namespace warpchol::fem
