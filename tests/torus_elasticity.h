#pragma once

/**
 * @file
 * The elasticity system the solver tests share: a generated torus of about 700 vertices,
 * every 97th vertex fixed, its implicit Euler matrix at rest.
 */

#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/mesh/mesh_generators.h>

#include <deal.II/grid/tria.h>

#include <memory>
#include <vector>

namespace tests
{
  /** The torus, its body and its system matrix at rest (assembled). */
  struct TorusElasticity
  {
    dealii::Triangulation<3>                  triangulation;
    std::unique_ptr<warpchol::fem::ElasticBody>  body;
    warpchol::fem::SystemCoefficients         coefficients =
      warpchol::fem::SystemCoefficients::implicit_euler(0.01, 0, 0);
    std::unique_ptr<warpchol::fem::SystemMatrix> system;

    TorusElasticity()
    {
      using namespace warpchol;
      fem::create_torus(triangulation, fem::torus_with_about(0.3, 0.1, 700));
      std::vector<bool> fixed(triangulation.n_vertices(), false);
      for (unsigned int v = 0; v < triangulation.n_vertices(); v += 97)
        fixed[v] = true;
      body   = std::make_unique<fem::ElasticBody>(triangulation, fem::Material{50, 0.45, 20},
                                                fem::MassMatrix::lumped, fixed);
      system = std::make_unique<fem::SystemMatrix>(*body, coefficients);
      system->assemble([&](const unsigned int e, fem::ElementMatrix &m) {
        m = fem::rest_element_matrix(*body, e, coefficients);
      });
    }
  };

  /** warpchol's solver as the solver tests factor the torus: supernodal, METIS ordering. */
  inline warpchol::cholesky::SparseCholesky supernodal_metis_solver()
  {
    warpchol::cholesky::SparseCholesky::Settings settings;
    settings.ordering.method = warpchol::cholesky::OrderingMethod::metis;
    settings.method          = warpchol::cholesky::FactorizationMethod::supernodal;
    return warpchol::cholesky::SparseCholesky(settings);
  }
} // namespace tests
