/**
 * warpchol: run a soft-body scene described by a parameter file.
 *
 *   warpchol PARAMS.prm [--resume]
 *   mpirun -np N warpchol PARAMS.prm
 *   warpchol PARAMS.prm --distributed
 *   warpchol --print-parameters [FILE]
 *
 * See the scenes in parameters/ (parameters/README.md) and doc/simulation.md. The program chooses between the serial run
 * (warpchol::app::main, which the tests call as well) and the distributed one
 * (warpchol::distributed::run_distributed), so that app/ needs nothing of distributed/,
 * which builds on it.
 */

#include <warpchol/app/simulation.h>
#include <warpchol/cholesky/blas.h>
#include <warpchol/distributed/distributed_simulation.h>

#include <iostream>
#include <string>
#include <vector>

int main(int argc, char **argv)
{
  warpchol::cholesky::blas::restart_with_blas_kernels_for_this_cpu(argv);
  const std::vector<std::string> arguments(argv + 1, argv + argc);
  const bool names_a_file = !arguments.empty() && !arguments[0].empty() && arguments[0][0] != '-';
  // Distributed when asked for, or when an MPI launcher started several processes.
  if (names_a_file && ((arguments.size() == 2 && arguments[1] == "--distributed") ||
                       (arguments.size() == 1 && warpchol::distributed::launched_on_several_ranks())))
    return warpchol::distributed::run_distributed(argc, argv, arguments[0], std::cout, std::cerr);
  return warpchol::app::main(argc, argv, std::cout, std::cerr);
}
