#pragma once

#include <warpchol/app/parameters/parameter_file.h>
#include <warpchol/backends/linear_solver.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/models/model_type.h>
#include <warpchol/models/step_strategy.h>

#include <deal.II/base/parameter_handler.h>

#include <string>

/**
 * @file
 * The subsections of a step: its time stepping ("Time stepping"), the elasticity model
 * ("Model"), the solver of a serial run ("Solver") and that of a run under MPI
 * ("Distributed").
 */
namespace warpchol::app
{
  namespace parameters
  {
    /** Subsection "Time stepping". */
    struct TimeStepping
    {
      double       time_step          = 0.01;
      unsigned int n_steps            = 100;
      double       rayleigh_mass      = 0;
      double       rayleigh_stiffness = 0;
      /** Stop before n_steps once the kinetic energy falls below this (J); 0: never. */
      double       rest_kinetic_energy = 0;
      /**
       * Stop with a SimulationError once the energy the body holds exceeds this many times
       * the energy put into it (fem::EnergyBalance); 0: never.
       */
      double       energy_growth_limit = 10;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /** Subsection "Model". */
    struct Model
    {
      fem::ModelType    type             = fem::ModelType::warp_canceling;
      double            rerotation_threshold = 0.05;
      /** > 0: the threshold adapts each step to keep the trajectory error near this. */
      double            target_error = 0;
      /** How a WCC step refreshes its factor and solves. */
      fem::StepStrategy strategy;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /** Subsection "Solver": parsed by the solver's own parsers, so new choices need no change here. */
    struct Solver
    {
      cholesky::SparseCholesky::Settings settings;
      /** Who factors and solves the step's system: warpchol's factor or a peer's. */
      backends::Settings                 backend;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /**
     * Subsection "Distributed": how a run under MPI (mpirun -np N, or --distributed) solves
     * the step's system, on the engines made for it (distributed/).
     */
    struct Distributed
    {
      /** "amg_cg" (Trilinos CG with ML AMG) or "mumps" (PETSc's MUMPS, direct). */
      std::string  linear_solver = "amg_cg";
      /** CG stops at |b - A x| <= tolerance |b|. */
      double       tolerance = 1e-8;
      unsigned int max_iterations = 1000;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };
  } // namespace parameters
} // namespace warpchol::app
