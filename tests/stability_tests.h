#pragma once

/**
 * @file
 * Helpers of the stability tests (stability_*.cc): a scene run with every model for a few
 * hundred steps, and one row per model and case of what the run did: whether its energy
 * stayed bounded by what was put in, whether every value stayed finite, whether every
 * factorization succeeded, and its largest energy ratio (fem::EnergyBalance: the energy the
 * body holds over the energy put into it; implicit Euler dissipates, so at most 1 up to the
 * linearization of the rotations).
 */

#include "simulation_tests.h"

#include <warpchol/app/parameters.h>
#include <warpchol/app/scene.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/dynamics/energy_balance.h>

#include <Eigen/LU>

#include <iomanip>
#include <iostream>
#include <limits>
#include <regex>
#include <string>
#include <utility>
#include <vector>

namespace tests
{
  /** A run is bounded when its energy ratio never exceeds 1 + this. */
  constexpr double energy_tolerance = 0.1;
  /** A run stops once its energy ratio exceeds this (Time stepping/Energy growth limit's default). */
  constexpr double runaway_ratio = 10;

  /** The models of the tables: a label and the body of "subsection Model". */
  inline std::vector<std::pair<std::string, std::string>> stability_models()
  {
    return {{"linear", "  set Type = linear\n"},
            {"stiffness_warping", "  set Type = stiffness_warping\n"},
            {"corotational", "  set Type = corotational\n"},
            {"wcc_0.3", "  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n"},
            // auto chooses by measured times, so its trajectory is the exact one only to
            // CG's tolerance: a tight one makes the rows the same on a slow (sanitized) build.
            {"wcc_1_auto", "  set Type = warp_canceling\n  set Rerotation threshold = 1\n"
                           "  set Strategy = auto\n  set CG tolerance = 1e-10\n"},
            {"wcc_inf_precond", "  set Type = warp_canceling\n  set Rerotation threshold = inf\n"
                                "  set Strategy = preconditioned\n"}};
  }

  /**
   * The small torus of small_torus_scene() (200 vertices, 960 tets; far side held, near
   * side lifted by a tool, gravity, Rayleigh damping 0.1/0.1) with the settings the cases
   * vary; no Model subsection.
   */
  struct TorusCase
  {
    std::string youngs_modulus   = "50";
    std::string poisson_ratio    = "0.45";
    std::string time_step        = "0.01";
    std::string damping          = "0.1";
    std::string gravity          = "0, -9.81, 0";
    bool        fixed_far_side   = true;
    std::string tool_stiffness   = "20";
    std::string tool_velocity    = "0, 0.5, 0";
    std::string tool_duration    = "0.2";
    std::string angular_velocity = "0, 0, 0";

    std::string text() const
    {
      std::string result = "subsection Mesh\n  set Source = torus\n  set Torus toroidal cells = 8\nend\n"
                           "subsection Material\n  set Young's modulus = " + youngs_modulus +
                           "\n  set Poisson's ratio = " + poisson_ratio + "\nend\n"
                           "subsection Time stepping\n  set Time step = " + time_step +
                           "\n  set Rayleigh mass = " + damping + "\n  set Rayleigh stiffness = " +
                           damping + "\n  set Energy growth limit = 0\nend\n"
                           "subsection Gravity\n  set Acceleration = " + gravity + "\nend\n"
                           "subsection Initial state\n  set Angular velocity = " + angular_velocity +
                           "\nend\n";
      if (fixed_far_side)
        result += "subsection Fixed vertices\n  set Region = box\n  set Box lower corner = -1, -1, -1\n"
                  "  set Box upper corner = -0.33, 1, 1\nend\n";
      if (tool_stiffness != "0")
        result += "subsection Tool\n  set Region = sphere\n  set Sphere center = 0.4, 0, 0\n"
                  "  set Sphere radius = 0.06\n  set Spring stiffness = " + tool_stiffness +
                  "\n  set Velocity = " + tool_velocity + "\n  set Duration = " + tool_duration +
                  "\nend\n";
      return result;
    }
  };

  /** What a run did. */
  struct StabilityRun
  {
    unsigned int steps_done      = 0;
    bool         finite          = true;
    bool         factorizations  = true;
    /** The step whose energy ratio passed runaway_ratio (0: none). */
    unsigned int runaway_step    = 0;
    double       max_ratio       = 0;
    double       max_held_energy = 0;
    /** The smallest det F over the elements at the end (negative: inverted elements). */
    double       min_det_f       = 0;
    /** Inverted elements (det F <= 0): the most after any step, and at the end. */
    unsigned int max_inverted    = 0;
    unsigned int inverted_at_end = 0;
    /** The error that stopped the run, if any. */
    std::string  error;

    bool bounded() const
    {
      return finite && factorizations && runaway_step == 0 && max_ratio <= 1 + energy_tolerance;
    }
  };

  /** The elements of @p body with det F <= 0 at @p positions. */
  inline unsigned int inverted_elements(const warpchol::fem::ElasticBody        &body,
                                        const std::vector<warpchol::fem::Vector3> &positions)
  {
    unsigned int count = 0;
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      count += !(body.deformation_gradient(e, positions).determinant() > 0);
    return count;
  }

  /**
   * Run the scene of parameter text @p scene (without a Model subsection) with the model
   * section @p model for @p steps steps, from rest or from @p initial_positions and
   * @p initial_velocities (each if not empty), recording
   * the energy balance after every step.
   */
  inline StabilityRun run_stability_case(const std::string &scene, const std::string &model,
                                         const unsigned int                 steps,
                                         const std::vector<warpchol::fem::Vector3> &initial_positions = {},
                                         const std::vector<warpchol::fem::Vector3> &initial_velocities = {})
  {
    write_file("stability_case.prm", scene + "subsection Model\n" + model + "end\n");
    warpchol::app::Scene scene_built{warpchol::app::AllParameters("stability_case.prm")};
    auto                &integrator = scene_built.integrator();
    if (!initial_positions.empty())
      integrator.set_initial_positions(initial_positions);
    if (!initial_velocities.empty())
      integrator.set_initial_velocities(initial_velocities);
    warpchol::fem::EnergyBalance balance(scene_built.body());
    balance.record(integrator);
    StabilityRun run;
    try
      {
        for (unsigned int step = 1; step <= steps; ++step)
          {
            warpchol::fem::StepStatistics statistics;
            integrator.advance(statistics);
            balance.record(integrator);
            run.steps_done = step;
            run.max_inverted = std::max(run.max_inverted, inverted_elements(scene_built.body(), integrator.positions()));
            if (!balance.all_finite())
              break;
            if (balance.ratio() > runaway_ratio)
              {
                run.runaway_step = step;
                break;
              }
          }
      }
    catch (const warpchol::MatrixError &error)
      {
        run.error = error.what();
        // ImplicitEuler says "not finite" for velocities that overflow; anything else is a
        // factorization (or solve) that failed.
        if (run.error.find("not finite") != std::string::npos)
          run.finite = false;
        else
          run.factorizations = false;
      }
    run.finite          = run.finite && balance.all_finite();
    run.max_ratio       = balance.max_ratio();
    run.max_held_energy = balance.max_held_energy();
    const auto &body    = scene_built.body();
    run.inverted_at_end = inverted_elements(body, integrator.positions());
    run.min_det_f       = std::numeric_limits<double>::infinity();
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      run.min_det_f = std::min(run.min_det_f,
                               body.deformation_gradient(e, integrator.positions()).determinant());
    return run;
  }

  /** A ratio with two significant digits, or "> 10" for a runaway. */
  inline std::string rounded_ratio(const StabilityRun &run)
  {
    if (run.runaway_step > 0)
      return "> " + warpchol::format_number(runaway_ratio);
    return warpchol::format_number(run.max_ratio, 2);
  }

  /** Print a row "case | model: bounded yes, finite yes, factorizations ok, max energy ratio R". */
  inline void print_stability_row(const std::string &case_label, const std::string &model,
                                  const StabilityRun &run)
  {
    std::cout << std::left << std::setw(22) << case_label << " | " << std::setw(17) << model
              << " | bounded: " << (run.bounded() ? "yes" : "NO ")
              << ", finite: " << (run.finite ? "yes" : "NO ")
              << ", factorizations: " << (run.factorizations ? "ok  " : "FAIL")
              << ", max energy ratio " << rounded_ratio(run);
    if (run.runaway_step > 0)
      std::cout << " (runaway)";
    std::cout << std::endl;
    // What stopped the run, its figures masked (they depend on the last bits).
    if (!run.error.empty())
      std::cout << "  stopped: " << std::regex_replace(run.error, std::regex(R"([0-9][0-9.e+-]*)"), "#")
                << std::endl;
  }
} // namespace tests
