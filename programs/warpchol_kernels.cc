/**
 * warpchol-kernels: the cost per element of the element kernels (ns per tet) of a scene, on
 * every SIMD target this CPU runs, side by side: what each target gains, measured in one run.
 *
 *   warpchol-kernels PARAMS.prm [--steps N] [--targets avx512,avx2,...] [--rounds R] [--threads N]
 *
 * The scene runs N steps (default 20) with its own model first, so that the kernels are
 * timed on a deformed configuration; then each kernel is timed (best of five passes over
 * all the elements) on each target, kernel by kernel with the targets in turn, R rounds
 * (default 3), and the best of the rounds kept: a burst of load on a shared machine then
 * slows one round of one kernel on one target, not a target's column. --threads N sets
 * the threads (default 1: the per-core cost). Prints the machine (CPU, dgemm, read
 * bandwidth) first.
 */

#include <warpchol/app/command_line.h>
#include <warpchol/app/parameters.h>
#include <warpchol/app/scene.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/simd.h>
#include <warpchol/cholesky/blas.h>
#include <warpchol/reports/kernel_timing.h>
#include <warpchol/reports/machine.h>

#include <deal.II/base/multithread_info.h>

#include <iostream>
#include <sstream>

using namespace warpchol;

namespace
{
  const char *usage = "usage: warpchol-kernels PARAMS.prm [--steps N] [--targets T1,T2,...] [--rounds R] [--threads N]";

  void run(int argc, char **argv)
  {
    app::CommandLine         line(argc, argv);
    std::string              scene_file;
    unsigned int             steps   = 20;
    unsigned int             threads = 1;
    unsigned int             rounds  = 3;
    std::vector<std::string> targets = simd::available_targets();
    while (line.has_next())
      {
        const std::string argument = line.next();
        if (argument == "--steps")
          steps = static_cast<unsigned int>(line.integer_of(argument, 0, 100000));
        else if (argument == "--rounds")
          rounds = static_cast<unsigned int>(line.integer_of(argument, 1, 1000));
        else if (argument == "--threads")
          threads = static_cast<unsigned int>(line.integer_of(argument, 1, 1024));
        else if (argument == "--targets")
          {
            targets.clear();
            std::istringstream list(line.value_of(argument));
            for (std::string name; std::getline(list, name, ',');)
              targets.push_back(name);
          }
        else
          line.read_help_or_input_file(argument, usage, scene_file);
      }
    if (scene_file.empty())
      throw InputError(usage);
    for (const std::string &target : targets)
      try
        {
          simd::use_target(target);
        }
      catch (const std::invalid_argument &error)
        {
          throw InputError(std::string("--targets: ") + error.what());
        }
    dealii::MultithreadInfo::set_thread_limit(threads);
    simd::use_target("default");
    const app::DefaultTargets defaults = app::DefaultTargets::current();
    std::cout << app::describe_machine() << "\n";

    app::Scene scene{app::AllParameters(scene_file)};
    for (unsigned int step = 0; step < steps; ++step)
      {
        fem::StepStatistics statistics;
        scene.integrator().advance(statistics);
      }
    const std::vector<fem::Vector3> positions = scene.integrator().positions();
    const std::vector<app::KernelTimes> times = app::time_kernels_on_targets(scene, positions, targets, rounds);
    std::vector<std::pair<std::string, app::KernelTimes>> columns;
    for (std::size_t t = 0; t < targets.size(); ++t)
      columns.emplace_back(targets[t], times[t]);
    std::cout << scene_file << ", after " << steps << " steps, " << threads << " thread(s)\n";
    const fem::CellOrder &order = scene.cell_order();
    std::cout << "cells " << (order.sorted ? "sorted for locality" : "in the given order");
    if (order.given_misses > 0)
      std::cout << " (vertices missed per cell in a 16-cell window: given " << format_number(order.given_misses, 3)
                << ", sorted " << format_number(order.sorted_misses, 3) << ")";
    std::cout << "\n";
    app::print_kernel_table(std::cout, columns, scene.body().n_elements(), 0, defaults);
  }
} // namespace

int main(int argc, char **argv)
{
  cholesky::blas::restart_with_single_threaded_libraries(argv);
  return app::run_program("warpchol-kernels", [&] { run(argc, argv); });
}
