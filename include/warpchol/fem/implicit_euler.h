#pragma once

#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/elasticity_model.h>
#include <warpchol/fem/small_dense.h>
#include <warpchol/fem/system_matrix.h>

#include <vector>

/**
 * @file
 * Implicit Euler time stepping in velocity form, with the external loads of the scenes.
 */
namespace warpchol::fem
{
  /**
   * A pulling tool, as a surgical instrument grabs tissue: every vertex of a region is
   * tied by a spring of stiffness @p stiffness (N/m) to a target point that starts at the
   * vertex's rest position and moves with @p velocity until time @p duration, then stays.
   */
  struct PullingTool
  {
    std::vector<unsigned int> vertices;
    double                    stiffness = 0;
    Vector3                   velocity  = Vector3::Zero();
    double                    duration  = 0;

    /** How far the targets have moved at time @p time. */
    Vector3 target_offset(double time) const;
  };

  /** External loads. */
  struct Loads
  {
    /** Gravitational acceleration (m/s^2), applied as m_i g on every vertex. */
    Vector3 gravity = Vector3::Zero();
    /** A constant force per vertex (N); empty for none. */
    std::vector<Vector3> vertex_forces;
    /** The tool; no vertex for none. */
    PullingTool tool;

    /** Whether a load that does not vanish at rest (gravity, constant forces) acts. */
    bool has_static_load() const;
  };

  /**
   * One implicit Euler step in velocity form (DESIGN.md eq. 1):
   *   (M + dt B + dt^2 K) v(t+dt) = M v(t) + dt (f_ext + f_el(x(t)))
   *   x(t+dt) = x(t) + dt v(t+dt)
   * where the model supplies the matrix (rotated as it sees fit), its factor and the
   * elastic forces. The tool's springs are implicit: they add dt^2 k to the diagonal of A
   * (the same in every rotated frame) and dt k (target - x) to the right-hand side. Fixed
   * vertices stay at rest.
   */
  class ImplicitEuler
  {
  public:
    /**
     * The coefficients of A for time step @p time_step, Rayleigh damping (alpha M + beta K)
     * and the springs of @p loads' tool.
     */
    static SystemCoefficients coefficients(const ElasticBody &body, double time_step,
                                           double rayleigh_mass, double rayleigh_stiffness,
                                           const Loads &loads);

    /** Start at rest in the rest configuration at time 0. */
    ImplicitEuler(const ElasticBody &body, ElasticityModel &model, const Loads &loads,
                  double time_step);

    /**
     * Advance by one time step. Throws MatrixError "step N: ..." if the factorization
     * fails or a velocity is not finite, or so large that its square overflows (the
     * simulation diverged).
     */
    void advance(StepStatistics &statistics);

    const std::vector<Vector3> &positions() const;
    const std::vector<Vector3> &velocities() const;
    /** Displacements x - X per vertex. */
    std::vector<Vector3> displacements() const;
    double               time() const;
    unsigned int         step_number() const;

    double kinetic_energy() const;
    /** Elastic energy of the current positions, with fresh rotations where the model uses them. */
    double elastic_energy() const;

  private:
    const ElasticBody   &body;
    ElasticityModel     &model;
    const Loads          loads;
    const double         time_step;
    double               current_time = 0;
    unsigned int         steps_done   = 0;
    std::vector<Vector3> x;
    std::vector<Vector3> v;
    /** The velocities of the step before (empty before the first step). */
    std::vector<Vector3> previous_v;
    /** m_i g + constant forces: what does not change from step to step. */
    std::vector<Vector3> constant_forces;
  };
} // namespace warpchol::fem
