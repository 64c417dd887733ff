#pragma once

#include <warpchol/app/parameters.h>
#include <warpchol/app/simulation.h>

#include <ostream>

/**
 * @file
 * What a run prints about each body at its end (Simulation::print_summary()): the model and
 * the solver, the steps, the updates and refactorizations, the step strategy's refreshes
 * and choices, the surgery, the errors against exact corotation, the energy, the stages
 * and the times.
 */
namespace warpchol::app
{
  /**
   * The summary lines of @p body, run with @p parameters (the simulation's: Output/Print
   * timings leaves out what changes from run to run).
   */
  void print_body_summary(std::ostream &out, const SimulatedBody &body, const AllParameters &parameters);
} // namespace warpchol::app
