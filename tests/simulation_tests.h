#pragma once

/**
 * @file
 * Helpers of the simulation tests: scenes written as parameter files in the test's working
 * directory, run for a number of steps through the application's own classes.
 */

#include "tests.h"

#include <warpchol/app/parameters.h>
#include <warpchol/app/scene.h>
#include <warpchol/app/simulation.h>
#include <warpchol/dynamics/implicit_euler.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

namespace tests
{
  /**
   * Run "warpchol ARGUMENTS" as the program runs: "MESSAGE [exit S]", its error line
   * without the newline ("NO ERROR" if none), ", SEVERAL LINES" added if it is not one line.
   */
  inline std::string run_warpchol(const std::vector<std::string> &arguments)
  {
    std::vector<const char *> argv{"warpchol"};
    for (const auto &argument : arguments)
      argv.push_back(argument.c_str());
    std::ostringstream out, err;
    const int          status  = warpchol::app::main(argv.size(), argv.data(), out, err);
    std::string        message = err.str();
    if (!message.empty() && message.back() == '\n')
      message.pop_back();
    return (message.empty() ? "NO ERROR" : message) + " [exit " + std::to_string(status) +
           (message.find('\n') == std::string::npos ? "" : ", SEVERAL LINES") + "]";
  }

  /** Write @p text to @p filename (in the test's working directory). */
  inline void write_file(const std::string &filename, const std::string &text)
  {
    std::ofstream(filename) << text;
  }

  /**
   * A small torus scene: 8 toroidal cells, no refinement (200 vertices, 960 tets), held on
   * its far side, lifted by a tool on the near side and pulled down by gravity, with
   * damping; @p model_section is the body of "subsection Model".
   */
  inline std::string small_torus_scene(const std::string &model_section,
                                        const std::string &mass_matrix = "lumped")
  {
    return "subsection Mesh\n"
           "  set Source = torus\n"
           "  set Torus toroidal cells = 8\n"
           "end\n"
           "subsection Material\n"
           "  set Mass matrix = " + mass_matrix + "\n"
           "end\n"
           "subsection Time stepping\n"
           "  set Time step = 0.01\n"
           "  set Rayleigh mass = 0.1\n"
           "  set Rayleigh stiffness = 0.1\n"
           "end\n"
           "subsection Model\n" + model_section + "end\n"
           "subsection Fixed vertices\n"
           "  set Region = box\n"
           "  set Box lower corner = -1, -1, -1\n"
           "  set Box upper corner = -0.33, 1, 1\n"
           "end\n"
           "subsection Gravity\n"
           "  set Acceleration = 0, -9.81, 0\n"
           "end\n"
           "subsection Tool\n"
           "  set Region = sphere\n"
           "  set Sphere center = 0.4, 0, 0\n"
           "  set Sphere radius = 0.06\n"
           "  set Spring stiffness = 20\n"
           "  set Velocity = 0, 0.5, 0\n"
           "  set Duration = 0.2\n"
           "end\n";
  }

  /** @p text without its "subsection NAME ... end" (the first one). */
  inline std::string without_subsection(std::string text, const std::string &name)
  {
    const auto begin = text.find("subsection " + name + "\n");
    if (begin != std::string::npos)
      text.erase(begin, text.find("end\n", begin) + 4 - begin);
    return text;
  }

  /** Build the scene of parameter file @p filename (written from @p text) and run @p steps steps. */
  inline std::vector<warpchol::fem::Vector3> run_scene(const std::string &filename,
                                                       const std::string &text,
                                                       const unsigned int steps)
  {
    write_file(filename, text);
    warpchol::app::Scene scene{warpchol::app::AllParameters(filename)};
    for (unsigned int step = 0; step < steps; ++step)
      {
        warpchol::fem::StepStatistics statistics;
        scene.integrator().advance(statistics);
      }
    return scene.integrator().positions();
  }

  /** max_i |a_i - b_i| / max_i |b_i - rest_i|: the difference relative to the motion. */
  inline double relative_difference(const std::vector<warpchol::fem::Vector3> &a,
                                    const std::vector<warpchol::fem::Vector3> &b,
                                    const std::vector<warpchol::fem::Vector3> &rest)
  {
    double difference = 0, motion = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
      {
        difference = std::max(difference, (a[i] - b[i]).norm());
        motion     = std::max(motion, (b[i] - rest[i]).norm());
      }
    return difference / motion;
  }
} // namespace tests
