// Every bad input is rejected with one line that names the file, line, entry, cell or step,
// and warpchol exits with status 2: malformed or out-of-range parameters, unknown entries,
// missing or broken mesh files, inverted and degenerate tetrahedra, a missing fixed vertex
// where rest is awaited. A failed factorization names the step, column and vertex.

#include "simulation_tests.h"

#include <warpchol/app/simulation.h>
#include <warpchol/dynamics/implicit_euler.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/models/elasticity_model.h>

#include <regex>
#include <sstream>

using namespace warpchol;

namespace
{
  /**
   * A small valid scene (a box of 96 tetrahedra, or the mesh of @p mesh_entries) with
   * @p extra appended.
   */
  std::string scene(const std::string &extra,
                    const std::string &mesh_entries = "  set Source = box\n  set Box subdivisions = 2, 1, 1\n")
  {
    return "subsection Mesh\n" + mesh_entries + "end\n"
           "subsection Time stepping\n  set Number of steps = 2\nend\n"
           "subsection Output\n  set Print timings = false\nend\n" +
           extra;
  }

  /** Run "warpchol ARGUMENTS" and print the label, the error line and the exit status. */
  void run(const std::string &label, const std::vector<std::string> &arguments)
  {
    std::cout << label << ": " << tests::run_warpchol(arguments) << std::endl;
  }

  void run_scene(const std::string &label, const std::string &filename, const std::string &text)
  {
    tests::write_file(filename, text);
    run(label, {filename});
  }

  /** Gmsh 1 file with the unit tetrahedron and a second one on top of it. */
  std::string gmsh_two_tetrahedra(const std::string &second_tetrahedron_line,
                                  const std::string &fifth_node = "5 1 1 1")
  {
    return "$NOD\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n" + fifth_node + "\n$ENDNOD\n$ELM\n2\n"
           "1 4 1 1 4 1 2 3 4\n" + second_tetrahedron_line + "\n$ENDELM\n";
  }

  /** A model whose matrix is indefinite from its first step on (c_M < 0). */
  class IndefiniteModel : public fem::ElasticityModel
  {
  public:
    IndefiniteModel(const fem::ElasticBody &body, const fem::SystemCoefficients &coefficients)
      : ElasticityModel(body, coefficients, cholesky::SparseCholesky::Settings())
    {}
    std::string name() const override
    {
      return "indefinite";
    }
    void prepare_step(const std::vector<fem::Vector3> &, const std::vector<fem::Vector3> &,
                      fem::StepStatistics &statistics) override
    {
      system.assemble([&](const unsigned int e, fem::ElementMatrix &matrix) {
        matrix = fem::rest_element_matrix(body, e, coefficients);
      });
      factorize(statistics);
    }
    void add_elastic_forces(const std::vector<fem::Vector3> &, std::vector<fem::Vector3> &) const override
    {}
  };
} // namespace

// One bad input after another, in the order of the .output file: a list, not an algorithm.
int main()
{
  // The valid scene runs: the checks below fail for their own reason.
  run_scene("valid scene", "valid.prm", scene(""));

  std::cout << "-- command line" << std::endl;
  run("no argument", {});
  run("missing parameter file", {"no_such_file.prm"});
  run("two arguments", {"valid.prm", "valid.prm"});

  std::cout << "-- parameter files" << std::endl;
  run_scene("malformed line", "malformed.prm", scene("subsection Material\n  sett Density = 3\nend\n"));
  run_scene("unknown entry", "unknown_entry.prm", scene("subsection Material\n  set Youngs modulus = 3\nend\n"));
  run_scene("unknown subsection", "unknown_subsection.prm", scene("subsection Materials\n  set Density = 3\nend\n"));
  run_scene("nu = 0.5", "nu_half.prm", scene("subsection Material\n  set Poisson's ratio = 0.5\nend\n"));
  run_scene("nu = 0.7", "nu_large.prm", scene("subsection Material\n  set Poisson's ratio = 0.7\nend\n"));
  run_scene("negative E", "negative_e.prm", scene("subsection Material\n  set Young's modulus = -50\nend\n"));
  run_scene("E = 0", "zero_e.prm", scene("subsection Material\n  set Young's modulus = 0\nend\n"));
  run_scene("negative density", "negative_density.prm", scene("subsection Material\n  set Density = -1\nend\n"));
  run_scene("density = 0", "zero_density.prm", scene("subsection Material\n  set Density = 0\nend\n"));
  run_scene("negative time step", "negative_dt.prm", scene("subsection Time stepping\n  set Time step = -0.01\nend\n"));
  run_scene("time step = 0", "zero_dt.prm", scene("subsection Time stepping\n  set Time step = 0\nend\n"));
  run_scene("energy growth limit below 1", "growth_limit.prm", scene("subsection Time stepping\n  set Energy growth limit = 0.5\nend\n"));
  run_scene("angular velocity of 2 components", "angular_velocity.prm", scene("subsection Initial state\n  set Angular velocity = 1, 2\nend\n"));
  run_scene("box grading below 1", "box_grading.prm", scene("subsection Mesh\n  set Source = box\n  set Box grading = 0.5\nend\n"));
  run_scene("threshold not a number", "threshold_text.prm", scene("subsection Model\n  set Rerotation threshold = often\nend\n"));
  run_scene("negative threshold", "threshold_negative.prm", scene("subsection Model\n  set Rerotation threshold = -1\nend\n"));
  run_scene("unknown model", "unknown_model.prm", scene("subsection Model\n  set Type = magic\nend\n"));
  run_scene("unknown step strategy", "unknown_strategy.prm", scene("subsection Model\n  set Strategy = fastest\nend\n"));
  run_scene("unknown iteration target", "unknown_target.prm", scene("subsection Model\n  set Iterate on = linear\nend\n"));
  run_scene("delayed top without supernodes", "delayed_left.prm",
            scene("subsection Model\n  set Strategy = delayed_top\nend\nsubsection Solver\n  set Method = left\nend\n"));
  run_scene("CG tolerance 0", "zero_tolerance.prm", scene("subsection Model\n  set CG tolerance = 0\nend\n"));
  run_scene("target error from an infinite threshold", "target_infinite.prm",
            scene("subsection Model\n  set Rerotation threshold = inf\n  set Target error = 0.01\nend\n"));
  run_scene("target error with CG on the corotational matrix", "target_cg.prm",
            scene("subsection Model\n  set Strategy = preconditioned\n  set Target error = 0.01\nend\n"));
  run_scene("too few thresholds for the bodies", "bodies_thresholds.prm",
            scene("subsection Bodies\n  set Number of bodies = 3\n  set Spacing = 1, 0, 0\n"
                  "  set Rerotation thresholds = 0, inf\nend\n"));
  run_scene("a body's threshold not a number", "bodies_threshold_text.prm",
            scene("subsection Bodies\n  set Number of bodies = 2\n  set Spacing = 1, 0, 0\n"
                  "  set Rerotation thresholds = 0, often\nend\n"));
  run_scene("an unknown model for a body", "bodies_model.prm",
            scene("subsection Bodies\n  set Number of bodies = 2\n  set Spacing = 1, 0, 0\n"
                  "  set Models = linear, magic\nend\n"));
  run_scene("a target error from a body's infinite threshold", "bodies_target.prm",
            scene("subsection Model\n  set Rerotation threshold = 0.3\n  set Target error = 0.01\nend\n"
                  "subsection Bodies\n  set Number of bodies = 2\n  set Spacing = 1, 0, 0\n"
                  "  set Rerotation thresholds = 0.3, inf\nend\n"));
  run_scene("bodies on top of each other", "bodies_spacing.prm",
            scene("subsection Bodies\n  set Number of bodies = 2\nend\n"));
  run_scene("unknown ordering", "unknown_ordering.prm", scene("subsection Solver\n  set Ordering = random\nend\n"));
  run_scene("unknown method", "unknown_method.prm", scene("subsection Solver\n  set Method = sideways\nend\n"));
  run_scene("vector with two numbers", "short_vector.prm", scene("subsection Gravity\n  set Acceleration = 0, -9.81\nend\n"));
  run_scene("vertex id out of range", "bad_id.prm", scene("subsection Fixed vertices\n  set Region = ids\n  set Vertex ids = 3, 999\nend\n"));
  run_scene("empty region", "empty_region.prm", scene("subsection Fixed vertices\n  set Region = sphere\n  set Sphere center = 5, 5, 5\n  set Sphere radius = 0.1\nend\n"));
  run_scene("rest awaited under gravity with nothing fixed", "no_fixed_vertex.prm",
            scene("subsection Gravity\n  set Acceleration = 0, -9.81, 0\nend\n"
                  "subsection Time stepping\n  set Rest kinetic energy = 1e-9\nend\n"));

  std::cout << "-- mesh files" << std::endl;
  // The box's entries left out: a mesh file uses none of them (they would be warned about).
  const auto mesh_scene = [](const std::string &mesh) {
    return scene("", "  set Source = file\n  set File = " + mesh + "\n");
  };
  run_scene("missing mesh file", "missing_mesh.prm", mesh_scene("no_such_mesh.msh"));
  run_scene("no mesh file given", "no_mesh.prm", mesh_scene(""));
  tests::write_file("mesh.off", "OFF\n");
  run_scene("unknown mesh format", "unknown_format.prm", mesh_scene("mesh.off"));
  tests::write_file("bad_node.msh", gmsh_two_tetrahedra("2 4 1 1 4 2 3 4 5", "5 1 one 1"));
  run_scene("malformed node line", "bad_node.prm", mesh_scene("bad_node.msh"));
  tests::write_file("undefined_node.msh", gmsh_two_tetrahedra("2 4 1 1 4 2 3 4 9"));
  run_scene("element refers to an undefined node", "undefined_node.prm", mesh_scene("undefined_node.msh"));
  tests::write_file("truncated.msh", "$NOD\n5\n1 0 0 0\n2 1 0 0\n");
  run_scene("truncated file", "truncated.prm", mesh_scene("truncated.msh"));
  tests::write_file("hexahedron.msh", gmsh_two_tetrahedra("2 5 1 1 8 1 2 3 4 5 1 2 3"));
  run_scene("hexahedron", "hexahedron.prm", mesh_scene("hexahedron.msh"));
  tests::write_file("binary.msh", "$MeshFormat\n2.2 1 8\n$EndMeshFormat\n");
  run_scene("binary Gmsh", "binary.prm", mesh_scene("binary.msh"));
  tests::write_file("inverted.msh", gmsh_two_tetrahedra("2 4 1 1 4 2 4 3 5"));
  run_scene("inverted tetrahedron", "inverted.prm", mesh_scene("inverted.msh"));
  tests::write_file("degenerate.msh", gmsh_two_tetrahedra("2 4 1 1 4 2 3 4 5", "5 0.5 0.5 0"));
  run_scene("degenerate tetrahedron", "degenerate.prm", mesh_scene("degenerate.msh"));
  tests::write_file("broken.vtu", "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\">\n<Unstruct");
  run_scene("broken VTU", "broken_vtu.prm", mesh_scene("broken.vtu"));
  tests::write_file("polydata.vtk", "# vtk DataFile Version 3.0\nsurface\nASCII\nDATASET POLYDATA\n"
                                    "POINTS 3 double\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 2\n");
  run_scene("legacy VTK without an unstructured grid", "polydata.prm", mesh_scene("polydata.vtk"));

  std::cout << "-- failed factorization" << std::endl;
  {
    dealii::Triangulation<3> triangulation;
    fem::create_box(triangulation, fem::BoxGeometry());
    fem::ElasticBody body(triangulation, fem::Material(), fem::MassMatrix::lumped,
                          std::vector<bool>(triangulation.n_vertices(), false));
    const fem::SystemCoefficients coefficients = fem::SystemCoefficients::implicit_euler(0.01, 0, 0);
    fem::SystemCoefficients negative = coefficients;
    negative.mass                    = -1;
    // A model whose matrix is indefinite (c_M < 0) fails in its first step.
    IndefiniteModel    model(body, negative);
    fem::ImplicitEuler integrator(body, model, fem::Loads(), 0.01);
    tests::expect_error("indefinite in a step", [&] {
      fem::StepStatistics statistics;
      integrator.advance(statistics);
    });
  }
}
