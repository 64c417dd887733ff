/**
 * warpchol-torus-matrix: write the rest system matrix A = M + dt^2 K of an elastic torus
 * (or of a mesh file) as a symmetric Matrix Market file, for solver benchmarks.
 *
 *   warpchol-torus-matrix --dofs N --output FILE.mtx
 *   warpchol-torus-matrix --mesh MESH.msh --output FILE.mtx
 *
 * The torus is the report's: major radius 0.3 m, minor radius 0.1 m, E = 50 Pa,
 * nu = 0.45, density 20 kg/m^3, lumped mass, dt = 0.01 s, no damping and no fixed vertex
 * (so A is symmetric positive definite). --dofs picks the resolution with about N dofs.
 */

#include <warpchol/app/command_line.h>
#include <warpchol/app/output.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/mesh/mesh_readers.h>
#include <warpchol/sparse/conversions.h>
#include <warpchol/sparse/matrix_market.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>

namespace
{
  using namespace warpchol;

  const char *usage =
    "usage: warpchol-torus-matrix (--dofs N | --mesh MESH) --output FILE.mtx\n"
    "  --dofs N       generated torus (R = 0.3, r = 0.1) with about N dofs\n"
    "  --mesh MESH    a tetrahedral mesh file (.msh, .vtk, .vtu) instead\n"
    "  --output FILE  the Matrix Market file to write (lower triangle, symmetric)";

  struct Options
  {
    double      target_dofs = 0;
    std::string mesh_file;
    std::string output_file;
  };

  Options parse_command_line(const int argc, char **argv)
  {
    Options          options;
    app::CommandLine command_line(argc, argv);
    while (command_line.has_next())
      {
        const std::string argument = command_line.next();
        if (argument == "--dofs")
          {
            options.target_dofs = command_line.number_of(argument);
            if (!(options.target_dofs >= 30))
              throw InputError("--dofs: expected a number of dofs >= 30, got " + format_number(options.target_dofs));
          }
        else if (argument == "--mesh")
          options.mesh_file = command_line.value_of(argument);
        else if (argument == "--output")
          options.output_file = command_line.value_of(argument);
        else if (argument == "--help" || argument == "-h")
          {
            std::cout << usage << std::endl;
            std::exit(0);
          }
        else
          throw InputError("unknown argument '" + argument + "'");
      }
    if (options.output_file.empty())
      throw InputError("--output is required");
    if ((options.target_dofs > 0) == !options.mesh_file.empty())
      throw InputError("give exactly one of --dofs and --mesh");
    return options;
  }

  void run(const Options &options)
  {
    dealii::Triangulation<3> triangulation;
    if (options.mesh_file.empty())
      {
        const fem::TorusGeometry torus = fem::torus_with_about(
          0.3, 0.1, static_cast<std::size_t>(std::lround(options.target_dofs / 3)));
        fem::create_torus(triangulation, torus);
        std::cout << "torus: R = 0.3, r = 0.1, " << torus.toroidal_cells << " toroidal cells, "
                  << torus.refinements << " refinements" << std::endl;
      }
    else
      fem::read_mesh(options.mesh_file, triangulation);

    const fem::Material material{50, 0.45, 20};
    const double        time_step = 0.01;
    const fem::ElasticBody body(triangulation, material, fem::MassMatrix::lumped,
                                std::vector<bool>(triangulation.n_vertices(), false));
    fem::SystemMatrix system(body, fem::SystemCoefficients::implicit_euler(time_step, 0, 0));
    const fem::SystemCoefficients coefficients =
      fem::SystemCoefficients::implicit_euler(time_step, 0, 0);
    system.assemble([&](const unsigned int e, fem::ElementMatrix &matrix) {
      matrix = fem::rest_element_matrix(body, e, coefficients);
    });
    const sparse::CSCMatrix lower = sparse::lower_triangle(system.csc());
    // Its folder too, as warpchol makes its output's (the pages write to output/benchmarks/).
    const std::string folder = std::filesystem::path(options.output_file).parent_path().string();
    if (!folder.empty())
      app::create_directory(folder);
    sparse::write_matrix_market(lower, options.output_file);
    std::cout << "vertices " << body.n_vertices() << ", tets " << body.n_elements() << ", n "
              << system.size() << ", nnz(lower) " << lower.n_nonzeros() << " -> "
              << options.output_file << std::endl;
  }
} // namespace

int main(int argc, char **argv)
{
  return warpchol::app::run_program("warpchol-torus-matrix", [&] { run(parse_command_line(argc, argv)); });
}
