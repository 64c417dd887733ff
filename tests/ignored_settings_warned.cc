// A setting that the chosen option leaves unused does not stop the run: it is named in a
// warning, "FILE:LINE: Subsection/Entry = value: ignored with CHOICE", in every subsection
// that has such choices; a file that sets only what its choices use gets none. And where
// the intent is plain, the file is taken as written: Fixed vertices/Vertex ids without a
// Region holds those vertices (Region = ids), in the program's run as in the scene. A serial
// run names what it ignores of Distributed, a distributed one what it ignores of Solver; an
// entry's old name is read as its new one, with a warning that names both.

#include "simulation_tests.h"

#include <warpchol/app/parameters.h>
#include <warpchol/app/scene.h>

using namespace warpchol;

namespace
{
  const std::string base = "subsection Mesh\n"
                           "  set Source = torus\n"
                           "  set Torus toroidal cells = 8\n"
                           "end\n"
                           "subsection Time stepping\n"
                           "  set Number of steps = 3\n"
                           "end\n"
                           "subsection Output\n"
                           "  set Directory = results\n"
                           "  set Print timings = false\n"
                           "end\n";

  /** The warnings of @p text, read as case.prm for @p run, one per line ("none" if there is none). */
  void print_warnings(const std::string &label, const std::string &text,
                      const app::RunKind run = app::RunKind::serial)
  {
    tests::write_file("case.prm", base + text);
    const app::AllParameters parameters("case.prm", run);
    std::cout << label << ":";
    if (parameters.warnings.empty())
      std::cout << " none";
    std::cout << "\n";
    for (const std::string &warning : parameters.warnings)
      std::cout << "  " << warning << "\n";
  }
} // namespace

int main()
{
  print_warnings("only what the choices use", "subsection Fixed vertices\n  set Region = box\n"
                                              "  set Box lower corner = -1, -1, -1\n"
                                              "  set Box upper corner = -0.33, 1, 1\nend\n");
  std::vector<std::pair<std::string, std::string>> cases = {
    {"Mesh", "subsection Mesh\n  set Box grading = 2\n  set Refinements = 1\nend\n"},
    {"Material", "subsection Material\n  set Total mass = 1\n  set Density = 30\nend\n"},
    {"Model, not WCC", "subsection Model\n  set Type = corotational\n  set Rerotation threshold = 0.3\nend\n"},
    {"Model, partial", "subsection Model\n  set Strategy = partial\n  set CG tolerance = 1e-4\n"
                       "  set Background lag = 2\nend\n"},
    {"Solver", "subsection Solver\n  set Tolerance = 1e-8\n  set Top flops fraction = 0.3\nend\n"},
    {"Fixed vertices", "subsection Fixed vertices\n  set Region = box\n  set Box upper corner = 1, 1, 1\n"
                       "  set Sphere radius = 0.1\n  set Vertex ids = 1, 2\nend\n"},
    {"Region force", "subsection Region force\n  set Total force = 0, 1, 0\nend\n"},
    {"Tool", "subsection Tool\n  set Region = sphere\n  set Sphere radius = 0.05\n  set Spring stiffness = 10\n"
             "  set Box lower corner = 0, 0, 0\nend\n"},
    {"Cut", "subsection Cut\n  set Blade start = 0, 0, 0\nend\n"},
    {"Grasp", "subsection Grasp 2\n  set Grasp time = 0.1\nend\n"},
    {"Material change", "subsection Material change\n  set Stiffness factor = 2\nend\n"},
    {"Bodies", "subsection Bodies\n  set Spacing = 1, 0, 0\nend\n"},
    {"Output", "subsection Output\n  set VTU precision = float64\nend\n"},
    {"Model, background", "subsection Model\n  set Strategy = background\n  set Rerotation threshold = 0.3\nend\n"},
    {"Bodies' own models and thresholds",
     "subsection Model\n  set Type = corotational\n  set Rerotation threshold = 0.3\nend\n"
     "subsection Bodies\n  set Number of bodies = 2\n  set Spacing = 1, 0, 0\n"
     "  set Models = warp_canceling, linear\n  set Rerotation thresholds = 0.2, 0.2\nend\n"},
    {"Bodies, no WCC", "subsection Model\n  set Type = linear\nend\n"
                       "subsection Bodies\n  set Rerotation thresholds = 0.2\nend\n"},
    {"Solver, method", "subsection Solver\n  set Method = left\n  set Change method = update\nend\n"},
    {"Solver, a peer's factor", "subsection Solver\n  set Backend = cholmod\n  set Method = left\n"
                                "  set Change method = update\n  set Preconditioner precision = half\nend\n"},
    {"Solver, SOFA's warp preconditioner",
     "subsection Model\n  set Type = corotational\n  set Rerotation threshold = 0.2\nend\n"
     "subsection Solver\n  set Backend = warp_preconditioned_cg\n  set Tolerance = 1e-6\n"
     "  set Change method = update\nend\n"},
    {"Obstacle", "subsection Obstacle\n  set Type = sphere\n  set Point = 2, 0, 0\n  set Radius = 0.1\n"
                 "  set Normal = 1, 0, 0\nend\nsubsection Obstacle 2\n  set Friction = 0.3\nend\n"},
    {"Contact", "subsection Contact\n  set Tolerance = 1e-10\nend\n"},
    {"Contact, penalty", "subsection Obstacle\n  set Type = plane\n  set Point = 0, -5, 0\n  set Normal = 0, 1, 0\n"
                         "  set Friction = 0.5\nend\nsubsection Contact\n  set Method = penalty\n"
                         "  set Max iterations = 50\n  set Compliance = full solves\nend\n"},
    {"Contact, constraints", "subsection Obstacle\n  set Type = plane\n  set Point = 0, -5, 0\n"
                             "  set Normal = 0, 1, 0\nend\nsubsection Contact\n  set Penalty stiffness = 1e5\nend\n"},
    {"Contact, full solves", "subsection Obstacle\n  set Type = plane\n  set Point = 0, -5, 0\n"
                             "  set Normal = 0, 1, 0\nend\nsubsection Contact\n  set Compliance = full solves\n"
                             "  set Compliance lag = true\nend\n"},
    {"Contact, an iterating strategy",
     "subsection Model\n  set Type = warp_canceling\n  set Strategy = preconditioned\nend\n"
     "subsection Obstacle\n  set Type = plane\n  set Point = 0, -5, 0\n  set Normal = 0, 1, 0\nend\n"
     "subsection Contact\n  set Compliance lag = true\nend\n"},
    {"Distributed, serial run", "subsection Distributed\n  set Linear solver = mumps\n  set Tolerance = 1e-10\nend\n"},
    {"Old names", "subsection Model\n  set Update threshold = 0.2\nend\n"
                  "subsection Bodies\n  set Update thresholds = 0.2\nend\n"}};
  tests::write_file("path.csv", "0, 0.4, 0, 0\n1, 0.4, 0.1, 0\n");
  cases.emplace_back("Tool, path", "subsection Tool\n  set Region = sphere\n  set Sphere center = 0.4, 0, 0\n"
                                   "  set Sphere radius = 0.05\n  set Spring stiffness = 10\n"
                                   "  set Path file = path.csv\n  set Duration = 0.5\nend\n");
  cases.emplace_back("Grasp, path", "subsection Grasp\n  set Sphere radius = 0.05\n  set Path file = path.csv\n"
                                    "  set Duration = 0.5\n  set Sphere center = 0.4, 0, 0\nend\n");
  for (const auto &[label, text] : cases)
    print_warnings(label, text);
  const std::string distributed = "subsection Distributed\n  set Linear solver = mumps\n  set Tolerance = 1e-10\nend\n";
  print_warnings("Distributed, distributed run", distributed, app::RunKind::distributed);
  print_warnings("Solver, distributed run", "subsection Solver\n  set Ordering = amd\nend\n", app::RunKind::distributed);
  print_warnings("Instruments and output, distributed run",
                 "subsection Cut\n  set Blade start = 0.3, -1, 0\n  set Blade end = 0.3, 1, 0\n"
                 "  set Velocity = 0, 0, 1\n  set Duration = 0.1\nend\n"
                 "subsection Output\n  set Exact steps timed = 2\nend\n",
                 app::RunKind::distributed);
  {
    print_warnings("Old name, its value", "subsection Model\n  set Update threshold = 0.2\nend\n");
    const app::AllParameters parameters("case.prm");
    std::cout << "  Model/Rerotation threshold: " << parameters.model.rerotation_threshold << "\n";
  }

  // Vertex ids without a Region: those vertices are held, and said nothing about.
  const std::string ids = "subsection Fixed vertices\n  set Vertex ids = 0, 1, 2, 3\nend\n";
  print_warnings("Vertex ids without a Region", ids);
  {
    const app::AllParameters parameters("case.prm");
    const app::Scene         scene(parameters);
    std::cout << "  region " << parameters.fixed_vertices.region.kind << ", fixed vertices:";
    for (const unsigned int v : scene.fixed_vertices())
      std::cout << " " << v;
    std::cout << "\n";
  }
  // The program: warnings first on standard error, then the run, exit 0.
  tests::write_file("run.prm", base + ids + "subsection Fixed vertices\n  set Sphere radius = 0.1\nend\n");
  std::cout << "warpchol run.prm: " << tests::run_warpchol({"run.prm"}) << "\n";
  // A serial run of a file written for a distributed one says what it leaves unused.
  tests::write_file("serial.prm", base + "subsection Distributed\n  set Linear solver = mumps\nend\n");
  std::cout << "warpchol serial.prm: " << tests::run_warpchol({"serial.prm"}) << "\n";
}
