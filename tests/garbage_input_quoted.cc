// What an input file holds is quoted in an error as a short, printable excerpt (at most 40
// characters, other bytes as \xNN, "(binary data)" when it looks binary), never echoed as
// it is: a binary .prm, control bytes and a very long line in a .prm, a garbage Gmsh line,
// a binary Matrix Market file. Every message is checked to be one printable line.

#include "simulation_tests.h"

#include <warpchol/app/simulation.h>
#include <warpchol/mesh/mesh_readers.h>
#include <warpchol/sparse/matrix_market.h>

#include <sstream>

using namespace warpchol;

namespace
{
  /** Print the message and whether it is one line of printable ASCII of at most 300 characters. */
  void show(const std::string &label, std::string message, const int status = -1)
  {
    if (!message.empty() && message.back() == '\n')
      message.pop_back();
    bool printable = message.size() <= 300;
    for (const char c : message)
      printable = printable && c >= 0x20 && c < 0x7f;
    std::cout << label << ": " << message;
    if (status >= 0)
      std::cout << " [exit " << status << "]";
    std::cout << (printable ? "" : " [NOT A SHORT PRINTABLE LINE]") << std::endl;
  }

  void run(const std::string &label, const std::string &parameter_file)
  {
    const char        *argv[] = {"warpchol", parameter_file.c_str()};
    std::ostringstream out, err;
    const int          status = app::main(2, argv, out, err);
    show(label, err.str(), status);
  }

  template <typename Action>
  void expect_error(const std::string &label, const Action &action)
  {
    try
      {
        action();
        std::cout << label << ": NO ERROR" << std::endl;
      }
    catch (const Error &error)
      {
        show(label, error.what());
      }
  }

  /** @p n bytes from a fixed generator: binary garbage, the same on every run. */
  std::string garbage(const std::size_t n, const std::uint64_t seed)
  {
    tests::Random random(seed);
    std::string   bytes(n, '\0');
    for (auto &byte : bytes)
      byte = static_cast<char>(random.next() & 0xFF);
    return bytes;
  }
} // namespace

int main()
{
  std::cout << "-- helpers" << std::endl;
  std::cout << "quote of a short text: " << quote("set Density = 3") << std::endl;
  std::cout << "quote of 60 letters: " << quote(std::string(60, 'a')) << std::endl;
  std::cout << "quote of an escape sequence: " << quote("\x1b[31mred\x1b[0m") << std::endl;
  std::cout << "quote of UTF-8 text: " << quote("Poisson's ratio \xc2\xb5") << std::endl;
  tests::check("UTF-8 text does not look binary", !looks_binary("d\xc3\xa9j\xc3\xa0 vu, caf\xc3\xa9\n"));
  tests::check("random bytes look binary", looks_binary(garbage(200, 3)));

  std::cout << "-- parameter files" << std::endl;
  tests::write_file("garbage.prm", garbage(3000, 1));
  run("binary garbage", "garbage.prm");
  // ELF's magic, as if a program were given as the parameter file.
  tests::write_file("program.prm", std::string("\x7f" "ELF\x02\x01\x01\0\0\0\0\0\0\0\0\0", 16) + garbage(500, 2));
  run("a program", "program.prm");
  tests::write_file("escape.prm", "subsection Material\n  sett \x1b[2J\x1b[31m Density = 3\nend\n");
  run("a line with escape sequences", "escape.prm");
  tests::write_file("long_line.prm", "subsection Material\n  set " + std::string(5000, 'D') + " = 3\nend\n");
  run("an unknown entry of 5000 characters", "long_line.prm");
  tests::write_file("long_value.prm", "subsection Material\n  set Density = " + std::string(3000, '9') + "x\nend\n");
  run("a value of 3000 characters", "long_value.prm");
  tests::write_file("long_subsection.prm", "subsection " + std::string(2000, 'S') + "\nend\n");
  run("a subsection of 2000 characters", "long_subsection.prm");

  std::cout << "-- includes" << std::endl;
  tests::write_file("self.prm", "# comment\ninclude self.prm\n");
  run("a file that includes itself", "self.prm");
  tests::write_file("cycle_a.prm", "include cycle_b.prm\n");
  tests::write_file("cycle_b.prm", "subsection Material\nend\ninclude ./cycle_a.prm\n");
  run("a cycle of two files", "cycle_a.prm");
  tests::write_file("device.prm", "include /dev/zero\n");
  run("an endless device", "device.prm");
  tests::write_file("missing_include.prm", "include nowhere.prm\n");
  run("a missing file", "missing_include.prm");
  tests::write_file("material.prm", "subsection Material\n  set Density = 3\nend\n");
  tests::write_file("with_include.prm", "include material.prm\n");
  tests::check("an include is followed", app::AllParameters("with_include.prm").material.density == 3);

  std::cout << "-- meshes and matrices" << std::endl;
  tests::write_file("garbage.msh", garbage(2000, 4));
  expect_error("a binary .msh", [] {
    dealii::Triangulation<3> triangulation;
    fem::read_mesh("garbage.msh", triangulation);
  });
  tests::write_file("garbage_node.msh", "$NOD\n2\n1 0 0 0\n2 \x01\x02\x03\x1b[7m" + std::string(100, 'z') + " 0 0\n$ENDNOD\n");
  expect_error("a garbage node line", [] { fem::read_gmsh("garbage_node.msh"); });
  tests::write_file("garbage.vtk", "# vtk DataFile Version 3.0\ngarbage\nASCII\nDATASET UNSTRUCTURED_GRID\n" + garbage(300, 5));
  expect_error("legacy VTK with garbage", [] { fem::read_vtk("garbage.vtk"); });
  expect_error("a binary Matrix Market file", [] {
    std::istringstream stream(garbage(1000, 6));
    sparse::read_matrix_market(stream, "garbage.mtx");
  });
  expect_error("a garbage Matrix Market entry", [] {
    std::istringstream stream("%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 \x1b]0;pwned\x07" +
                              std::string(80, '7') + "\n");
    sparse::read_matrix_market(stream, "garbage_entry.mtx");
  });
}
