// Every bad input of contact is refused with one line naming the file, line and entry,
// and warpchol exits with status 2: an obstacle file that is missing, broken, empty or
// holds NaN; a negative or NaN friction coefficient; an obstacle inside the body at the
// start; a path file that ends before the run does, or whose lines do not all have the
// columns of a translation or of a translation and a rotation; more contacts than the
// cap; a peer's backend, which holds no factor of warpchol's to build W from; penalty
// springs with a stiffness of zero, or with a strategy whose CG would not see them.
// Gauss-Seidel stopping short of its tolerance is a warning with the residual, and the
// run goes on.

#include "simulation_tests.h"

#include <iostream>
#include <sstream>

namespace
{
  /**
   * A box of 96 tetrahedra (0.4 x 0.1 x 0.1 m) above a table 1 mm below it, under
   * gravity, with @p extra appended.
   */
  std::string scene(const std::string &extra)
  {
    return "subsection Mesh\n  set Source = box\n  set Box subdivisions = 2, 1, 1\nend\n"
           "subsection Time stepping\n  set Number of steps = 3\n  set Time step = 0.01\nend\n"
           "subsection Gravity\n  set Acceleration = 0, 0, -9.81\nend\n"
           "subsection Model\n  set Type = corotational\nend\n"
           "subsection Solver\n  set Method = supernodal\nend\n"
           "subsection Output\n  set Print timings = false\nend\n"
           "subsection Obstacle\n  set Type = plane\n  set Point = 0, 0, -0.001\n  set Friction = 0.5\nend\n" +
           extra;
  }

  void run_scene(const std::string &label, const std::string &filename, const std::string &text)
  {
    tests::write_file(filename, text);
    std::cout << label << ": " << tests::run_warpchol({filename}) << std::endl;
  }

  std::string obstacle_file(const std::string &file)
  {
    return "subsection Obstacle 2\n  set Type = surface\n  set File = " + file + "\nend\n";
  }
} // namespace

int main()
{
  run_scene("valid scene", "valid.prm", scene(""));

  std::cout << "-- obstacle files" << std::endl;
  run_scene("missing file", "missing.prm", scene(obstacle_file("no_such_surface.stl")));
  tests::write_file("broken.obj", "v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n");
  run_scene("broken OBJ", "broken.prm", scene(obstacle_file("broken.obj")));
  tests::write_file("face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  run_scene("face beyond the vertices", "face.prm", scene(obstacle_file("face.obj")));
  tests::write_file("empty.stl", "");
  run_scene("empty file", "empty.prm", scene(obstacle_file("empty.stl")));
  tests::write_file("no_triangle.obj", "# nothing but a comment\nv 0 0 0\n");
  run_scene("no triangle", "no_triangle.prm", scene(obstacle_file("no_triangle.obj")));
  tests::write_file("nan.stl", "solid table\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 nan\n"
                               "vertex 0 1 0\nendloop\nendfacet\nendsolid\n");
  run_scene("NaN in an STL file", "nan.prm", scene(obstacle_file("nan.stl")));
  tests::write_file("polydata.vtk", "# vtk DataFile Version 3.0\nribs\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n"
                                    "0 0 0\n1 0 0\n0 1 0\nPOLYGONS 1 4\n3 0 1 5\n");
  run_scene("VTK polygon beyond the points", "polydata.prm", scene(obstacle_file("polydata.vtk")));

  std::cout << "-- friction" << std::endl;
  run_scene("negative friction", "negative_friction.prm",
            scene("subsection Obstacle\n  set Friction = -0.1\nend\n"));
  run_scene("NaN friction", "nan_friction.prm", scene("subsection Obstacle\n  set Friction = nan\nend\n"));

  std::cout << "-- placement and paths" << std::endl;
  run_scene("sphere inside the body", "inside.prm",
            scene("subsection Obstacle 2\n  set Type = sphere\n  set Point = 0.2, 0.05, 0.05\n"
                  "  set Radius = 0.01\nend\n"));
  run_scene("table through the body", "through.prm",
            scene("subsection Obstacle\n  set Point = 0, 0, 0.05\nend\n"));
  tests::write_file("short_path.csv", "time, x, y, z\n0, 0, 0, 0\n0.01, 0, 0, 0.001\n");
  run_scene("path ending before the run", "short_path.prm",
            scene("subsection Obstacle 2\n  set Type = sphere\n  set Point = 0.2, 0.05, 0.2\n"
                  "  set Radius = 0.01\n  set Path file = short_path.csv\nend\n"));
  // A path that turns the obstacle has 7 columns on every line, as its first.
  tests::write_file("turning_path.csv", "time, x, y, z, rx, ry, rz\n0, 0, 0, 0, 0, 0, 0\n0.1, 0, 0, 0.001\n");
  run_scene("turning path with a line of 4 columns", "turning_path.prm",
            scene("subsection Obstacle 2\n  set Type = sphere\n  set Point = 0.2, 0.05, 0.2\n"
                  "  set Radius = 0.01\n  set Path file = turning_path.csv\nend\n"));
  tests::write_file("five_columns.csv", "0, 0, 0, 0, 0\n0.1, 0, 0, 0.001, 0\n");
  run_scene("path of 5 columns", "five_columns.prm",
            scene("subsection Obstacle 2\n  set Type = sphere\n  set Point = 0.2, 0.05, 0.2\n"
                  "  set Radius = 0.01\n  set Path file = five_columns.csv\nend\n"));

  std::cout << "-- the solve" << std::endl;
  run_scene("more contacts than the cap", "cap.prm",
            scene("subsection Contact\n  set Alarm distance = 0.01\n  set Max contacts = 3\nend\n"));
  run_scene("a peer's backend", "peer.prm", scene("subsection Solver\n  set Backend = cholmod\nend\n"));
  run_scene("penalty springs with a stiffness of zero", "zero_penalty.prm",
            scene("subsection Contact\n  set Method = penalty\n  set Penalty stiffness = 0\nend\n"));
  run_scene("penalty springs with a strategy that iterates", "penalty_cg.prm",
            scene("subsection Model\n  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n"
                  "  set Strategy = auto\nend\nsubsection Contact\n  set Method = penalty\nend\n"));
  {
    // A warning on the standard error stream, not an error: the run goes on.
    std::ostringstream warnings;
    std::streambuf    *standard = std::cerr.rdbuf(warnings.rdbuf());
    run_scene("Gauss-Seidel stopping short", "short.prm",
              scene("subsection Contact\n  set Alarm distance = 0.01\n  set Max iterations = 1\n"
                    "  set Tolerance = 0\nend\n"));
    std::cerr.rdbuf(standard);
    std::string line = warnings.str();
    // The residual's digits depend on the platform's rounding: the message up to them.
    line = line.substr(0, line.find(" with residual"));
    std::cout << "  warning: " << line << std::endl;
  }
}
