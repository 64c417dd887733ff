#pragma once

#include <warpchol/dynamics/implicit_euler.h>

/**
 * @file
 * The energy balance of a run, to tell a stable simulation from one that gains energy.
 */
namespace warpchol::fem
{
  /**
   * The energy the body holds against the energy put into it, step after step.
   *
   * Held: kinetic + elastic + the tool's springs (never negative). Put in: the initial
   * energy + the work of the tool's moving targets + the energy the changes of the body
   * put in or took out at their steps (a stiffened strained region holds more: that is no
   * divergence) + the work of the constant loads (gravity, region forces: minus their
   * potential). ImplicitEuler's inequality
   *   total_energy <= initial_energy + external_work + change_energy
   * says exactly held <= put in, and the ratio held / put in is the *energy ratio*: at most
   * 1 for a dissipative run (up to the linearization of the rotations), far above 1 for
   * one that diverges. Written this way the ratio has a positive denominator even when
   * gravity's potential is negative, and it does not depend on the energy's units.
   */
  class EnergyBalance
  {
  public:
    /**
     * For @p body: a held energy below 1/2 E V (1e-8)^2, that of a uniform strain of 1e-8,
     * counts as none. The elastic energy of a body at rest or moved rigidly is rounding
     * (strains of 1e-16), not energy to compare with the nothing put in.
     */
    explicit EnergyBalance(const ElasticBody &body);

    /** Which elastic energy record() takes. */
    enum class ElasticEnergy
    {
      /** That of the current positions: a pass over the elements. */
      current,
      /**
       * That of the start of the last step, which the step computed anyway: one step
       * late, enough to see an energy run away (it grows by orders of magnitude).
       */
      at_step_start
    };

    /** Record the state of @p integrator (at the start, or after a step). */
    void record(const ImplicitEuler &integrator, ElasticEnergy elastic = ElasticEnergy::current);

    /** Of the last record(): kinetic + elastic + the tool's springs (J). */
    double held_energy() const;
    /**
     * Of the last record(): initial energy + work of the tool and the constant loads + the
     * changes' energy + the work of the contact impulses (J: moving obstacles' work less
     * what friction dissipated).
     */
    double energy_put_in() const;
    /**
     * held / put in of the last record(); 0 while the body holds no energy (below the
     * noise floor), infinite if it holds some that nothing put in, NaN if an energy is not
     * finite.
     */
    double ratio() const;

    /** The largest ratio() and held energy over the records, and whether all were finite. */
    double max_ratio() const;
    double max_held_energy() const;
    bool   all_finite() const;

    /** Write the accounts to a checkpoint. */
    void save(BinaryWriter &writer) const;
    void load(BinaryReader &reader);

  private:
    double noise_floor   = 0;
    double held          = 0;
    double put_in        = 0;
    double largest_ratio = 0;
    double largest_held  = 0;
    bool   finite        = true;
  };
} // namespace warpchol::fem
