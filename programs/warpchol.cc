/**
 * warpchol: run a soft-body scene described by a parameter file.
 *
 *   warpchol PARAMS.prm
 *   warpchol --print-parameters [FILE]
 *
 * See the scenes in parameters/ and the README. The work is done by warpchol::app::main, which the
 * tests call as well.
 */

#include <warpchol/app/simulation.h>

#include <iostream>

int main(int argc, char **argv)
{
  return warpchol::app::main(argc, argv, std::cout, std::cerr);
}
