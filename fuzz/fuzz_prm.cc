/**
 * libFuzzer target: a parameter file read as warpchol reads it (app::AllParameters from a
 * file, then what the simulation asks of it before it reads a mesh: the scene's name, the
 * mesh path, each body's parameters).
 *
 * A bad file must end in warpchol::Error (InputError "FILE:LINE: entry: what is wrong");
 * anything else (a crash, a sanitizer report, a deal.II or standard exception, a hang) is
 * a finding: the program would print it as an internal error, with exit status 1.
 */

#include <warpchol/app/parameters.h>
#include <warpchol/base/exceptions.h>

#include <deal.II/base/exceptions.h>

#include "fuzz_input_file.h"

#include <cstdint>

/**
 * deal.II's exceptions (ParameterHandler's) collect the symbols of their stack when their message is
 * read, a large part of the time of an input that fails; the program cuts the stack off
 * their messages anyway.
 */
extern "C" int LLVMFuzzerInitialize(int *, char ***)
{
  dealii::deal_II_exceptions::suppress_stacktrace_in_exceptions();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, const std::size_t size)
{
  static warpchol::fuzz::InputFile input(".prm");
  const std::string               &filename = input.write(data, size);
  try
    {
      const warpchol::app::AllParameters parameters(filename);
      parameters.scene_name();
      parameters.mesh_file_path();
      for (unsigned int i = 0; i < parameters.bodies.count; ++i)
        parameters.body(i).exact_corotational();
    }
  catch (const warpchol::Error &)
    {
      // Refused with a message: what a bad parameter file should get.
    }
  return 0;
}
