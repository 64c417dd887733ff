// warpchol-contact-kernels: the compliance W = H A^-1 H^T of contact rows on an elasticity
// factor, by forward solves restricted to the rows' elimination-tree paths
// (SparseCholesky::compliance, BLAS-3 per supernode) against SOFA's way (a full-length
// forward solve per row, then the dense product over all n), on one thread; and projected
// Gauss-Seidel with the friction cone re-solved on a kept W (the haptic loop's cost).
//
//   warpchol-contact-kernels [--mesh meshes/sofa_liver.msh] [--refinements 2]
//                            [--rows 50,200,800] [--repeat 3] [--only w|gauss-seidel]
//
// Rows come three per surface vertex (a normal and two tangents), on the vertices nearest
// a point of the surface (a patch: a probe, a table) and on vertices spread at random over
// the surface. Prints the machine, then a Markdown table: m, placement, supernodes on the
// paths, milliseconds of both ways, their ratio and their largest difference; then
// Gauss-Seidel's milliseconds on every SIMD target this CPU runs (its product W lambda is
// an element-family kernel), the default target's over the fastest.

#include <warpchol/app/command_line.h>
#include <warpchol/reports/machine.h>
#include <warpchol/base/format.h>
#include <warpchol/base/simd.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/cholesky/blas.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/contact/contact_constraints.h>
#include <warpchol/contact/friction_cone_solver.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/mesh/mesh_readers.h>

#include <deal.II/grid/tria.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>

using namespace warpchol;

namespace
{
  const std::string usage =
    "usage: warpchol-contact-kernels [--mesh FILE] [--refinements R] [--rows M1,M2,...] [--repeat N] "
    "[--only w|gauss-seidel]";

  struct Options
  {
    std::string        mesh_file   = "meshes/sofa_liver.msh";
    unsigned int       refinements = 2;
    std::vector<Index> rows        = {50, 200, 800};
    int                repeat      = 3;
    /** "w" or "gauss-seidel": time that part alone (empty: both). */
    std::string only;
  };

  Options parse_command_line(const int argc, char **argv)
  {
    Options          options;
    app::CommandLine line(argc, argv);
    while (line.has_next())
      {
        const std::string argument = line.next();
        if (argument == "--mesh")
          options.mesh_file = line.value_of(argument);
        else if (argument == "--refinements")
          options.refinements = static_cast<unsigned int>(line.integer_of(argument, 0, 4));
        else if (argument == "--repeat")
          options.repeat = static_cast<int>(line.integer_of(argument, 1, 1000));
        else if (argument == "--only")
          {
            options.only = line.value_of(argument);
            if (options.only != "w" && options.only != "gauss-seidel")
              throw InputError("--only: '" + options.only + "' is neither w nor gauss-seidel");
          }
        else if (argument == "--rows")
          {
            options.rows.clear();
            std::istringstream list(line.value_of(argument));
            for (std::string item; std::getline(list, item, ',');)
              {
                char      *end = nullptr;
                const long m   = std::strtol(item.c_str(), &end, 10);
                if (item.empty() || *end != '\0' || m < 1 || m > 30000)
                  throw InputError("--rows: '" + item + "' is not a number of rows in [1, 30000]");
                options.rows.push_back(m);
              }
          }
        else
          {
            std::string ignored;
            line.read_help_or_input_file(argument, usage, ignored);
            throw InputError("unexpected argument '" + argument + "'; " + usage);
          }
      }
    return options;
  }

  /** The best wall-clock seconds of @p repeat runs of @p work. */
  template <typename Work>
  double best_seconds(const int repeat, const Work &work)
  {
    double best = std::numeric_limits<double>::infinity();
    for (int r = 0; r < repeat; ++r)
      {
        const Stopwatch stopwatch;
        work();
        best = std::min(best, stopwatch.seconds());
      }
    return best;
  }

  /** Contacts on @p vertices, each with the frame of the direction from the body's centre. */
  std::vector<fem::Contact> contacts_on(const std::vector<unsigned int> &vertices, const fem::ElasticBody &body,
                                        const fem::Vector3 &centre)
  {
    std::vector<fem::Contact> contacts;
    for (const unsigned int v : vertices)
      {
        fem::Contact contact;
        contact.vertex    = v;
        contact.normal    = (body.rest_positions()[v] - centre).normalized();
        contact.tangent_1 = contact.normal.unitOrthogonal();
        contact.tangent_2 = contact.normal.cross(contact.tangent_1);
        contacts.push_back(contact);
      }
    return contacts;
  }

  /** The first @p m columns of @p ht. */
  sparse::CSCMatrix first_columns(const sparse::CSCMatrix &ht, const Index m)
  {
    sparse::CSCMatrix part = sparse::CSCMatrix::zero(ht.n_rows, m);
    part.column_start.assign(ht.column_start.begin(), ht.column_start.begin() + m + 1);
    part.row_index.assign(ht.row_index.begin(), ht.row_index.begin() + part.column_start[m]);
    part.values.assign(ht.values.begin(), ht.values.begin() + part.column_start[m]);
    return part;
  }

  /** The rows of the kept W that Gauss-Seidel re-solves (the haptic loop's goal is stated at about 200). */
  constexpr Index kept_w_rows = 201;

  /**
   * Gauss-Seidel re-solved on a kept W of kept_w_rows rows (67 contacts on @p patch): every
   * contact pressed in at 1 cm/s with a sideways slide, friction 0.5, from zero impulses
   * each time.
   */
  void time_gauss_seidel_on_kept_w(const cholesky::SparseCholesky &solver, const fem::ElasticBody &body,
                                   const std::vector<unsigned int> &patch, const fem::Vector3 &centre)
  {
    const Index               m = kept_w_rows;
    const sparse::CSCMatrix    ht = first_columns(
      fem::ContactConstraints::constraint_columns(body, contacts_on(patch, body, centre), nullptr), m);
    const fem::ContactCompliance w = fem::ContactCompliance::whole(solver.compliance(ht));
    std::vector<double>          free_velocity(m), friction(m / 3, 0.5), lambda;
    for (Index j = 0; j < m / 3; ++j)
      {
        free_velocity[3 * j]     = -0.01;
        free_velocity[3 * j + 1] = 0.002 * std::cos(j);
        free_velocity[3 * j + 2] = 0.002 * std::sin(j);
      }
    fem::GaussSeidelSettings gauss_seidel;
    gauss_seidel.tolerance      = 1e-9;
    gauss_seidel.max_iterations = 1000;
    // Its product W lambda is a SIMD kernel of the element family: timed on every target.
    const std::vector<std::string> targets = simd::available_targets();
    std::vector<double>            seconds;
    fem::GaussSeidelResult         result;
    for (const std::string &target : targets)
      {
        simd::use_target(target);
        seconds.push_back(best_seconds(20, [&] {
          lambda.clear();
          result = fem::solve_friction_cone(w, free_velocity, friction, gauss_seidel, lambda);
        }));
      }
    simd::use_target("default");
    const std::string default_target  = simd::current_target(simd::Family::element);
    const double      fastest         = *std::min_element(seconds.begin(), seconds.end());
    double            default_seconds = fastest;
    std::cout << "Gauss-Seidel on a kept W of " << m << " rows (a patch, friction 0.5, tolerance 1e-9 m/s; "
              << result.iterations << " iterations, residual " << format_number(result.residual, 3)
              << " m/s), ms on each target:\n\n| kernel |";
    for (const std::string &target : targets)
      std::cout << " " << target << " |";
    std::cout << " default / fastest |\n|---|";
    for (std::size_t t = 0; t < targets.size(); ++t)
      std::cout << "---:|";
    std::cout << "---:|\n| Gauss-Seidel re-solve |";
    for (std::size_t t = 0; t < targets.size(); ++t)
      {
        std::cout << " " << format_number(1e3 * seconds[t], 3) << " |";
        if (targets[t] == default_target)
          default_seconds = seconds[t];
      }
    const double ratio = default_seconds / fastest;
    std::cout << " " << format_number(ratio, 3) << (ratio > app::slow_default_ratio ? " slow" : "") << " |\n\nthe default target ("
              << default_target << "): " << format_number(1e3 * default_seconds, 4) << " ms\n";
  }

  void run(const Options &options)
  {
    std::cout << app::describe_machine() << "\n";
    dealii::Triangulation<3> triangulation;
    fem::read_mesh(options.mesh_file, triangulation);
    triangulation.refine_global(options.refinements);
    const fem::ElasticBody body(triangulation, fem::Material{3000, 0.45, 1000}, fem::MassMatrix::lumped,
                                std::vector<bool>(triangulation.n_vertices(), false));
    const fem::SystemCoefficients coefficients = fem::SystemCoefficients::implicit_euler(0.01, 0, 0.01);
    fem::SystemMatrix             system(body, coefficients);
    system.assemble([&](const unsigned int e, fem::ElementMatrix &m) {
      m = fem::rest_element_matrix(body, e, coefficients);
    });
    cholesky::SparseCholesky::Settings settings;
    settings.method          = cholesky::FactorizationMethod::supernodal;
    settings.ordering.method = cholesky::OrderingMethod::metis;
    cholesky::SparseCholesky solver(settings);
    solver.factorize(system.lower());
    const std::vector<unsigned int> surface = fem::surface_vertices(body);
    std::cout << options.mesh_file << " refined " << options.refinements << " times: " << body.n_elements()
              << " tetrahedra, n = " << body.n_unknowns() << ", nnz(L) = " << solver.statistics().nnz_l << ", "
              << solver.statistics().n_supernodes << " supernodes, " << surface.size()
              << " surface vertices; one thread\n\n";

    fem::Vector3 centre = fem::Vector3::Zero();
    for (const fem::Vector3 &x : body.rest_positions())
      centre += x / body.n_vertices();
    // The patch holds Gauss-Seidel's contacts too, whatever --rows asks.
    const Index max_rows = options.only == "gauss-seidel" ?
                             kept_w_rows :
                             std::max(*std::max_element(options.rows.begin(), options.rows.end()), kept_w_rows);
    const auto  n_vertices = static_cast<std::size_t>((max_rows + 2) / 3);
    if (n_vertices > surface.size())
      throw InputError("--rows: " + std::to_string(max_rows) + " rows (at least Gauss-Seidel's " +
                       std::to_string(kept_w_rows) + ") need more surface vertices than the " +
                       std::to_string(surface.size()) + " of the mesh");
    // A patch: the surface vertices nearest the highest one; spread: a random sample.
    std::vector<unsigned int> patch = surface, spread = surface;
    const fem::Vector3 top = body.rest_positions()[*std::max_element(
      surface.begin(), surface.end(), [&](unsigned int a, unsigned int b) {
        return body.rest_positions()[a][2] < body.rest_positions()[b][2];
      })];
    std::sort(patch.begin(), patch.end(), [&](unsigned int a, unsigned int b) {
      return (body.rest_positions()[a] - top).norm() < (body.rest_positions()[b] - top).norm();
    });
    std::shuffle(spread.begin(), spread.end(), std::mt19937(1));
    patch.resize(n_vertices);
    spread.resize(n_vertices);

    if (options.only != "gauss-seidel")
      {
        std::cout << "| m | rows on | supernodes on the paths | flops paths / SOFA's | paths (ms) | SOFA's way (ms) | ratio | max difference / max W |\n"
                  << "|---:|---|---:|---:|---:|---:|---:|---:|\n";
        for (const auto &[placement, vertices] : {std::pair{"a patch", patch}, std::pair{"spread", spread}})
          {
            const sparse::CSCMatrix all = fem::ContactConstraints::constraint_columns(body, contacts_on(vertices, body, centre), nullptr);
            for (const Index m : options.rows)
              {
                const sparse::CSCMatrix ht = first_columns(all, m);
                std::vector<double>     by_paths, by_full_solves;
                cholesky::ComplianceStatistics paths_cost, full_cost;
                const double paths_seconds = best_seconds(options.repeat, [&] {
                  by_paths = solver.compliance(ht, cholesky::ComplianceMethod::paths, &paths_cost);
                });
                const double full_seconds  = best_seconds(std::max(1, options.repeat / 3), [&] {
                  by_full_solves = solver.compliance(ht, cholesky::ComplianceMethod::full_solves, &full_cost);
                });
                double largest = 0, difference = 0;
                for (std::size_t k = 0; k < by_paths.size(); ++k)
                  {
                    largest    = std::max(largest, std::abs(by_full_solves[k]));
                    difference = std::max(difference, std::abs(by_paths[k] - by_full_solves[k]));
                  }
                std::cout << "| " << m << " | " << placement << " | "
                          << format_number(100. * paths_cost.supernodes_visited / solver.statistics().n_supernodes, 3)
                          << " % | " << format_number(paths_cost.flops / full_cost.flops, 3) << " | " << format_number(1e3 * paths_seconds, 4) << " | " << format_number(1e3 * full_seconds, 4)
                          << " | " << format_number(full_seconds / paths_seconds, 3) << " | "
                          << format_number(difference / largest, 2) << " |\n";
              }
          }
        std::cout << "\n";
      }
    if (options.only != "w")
      time_gauss_seidel_on_kept_w(solver, body, patch, centre);
  }
} // namespace

int main(int argc, char **argv)
{
  cholesky::blas::restart_with_single_threaded_libraries(argv);
  return app::run_program("warpchol-contact-kernels", [&] { run(parse_command_line(argc, argv)); });
}
