#pragma once

#include <warpchol/app/parameters.h>
#include <warpchol/app/scene_mesh.h>
#include <warpchol/dynamics/implicit_euler.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/mesh/mesh_readers.h>
#include <warpchol/models/elasticity_model.h>

#include <deal.II/grid/tria.h>

#include <memory>
#include <string>
#include <vector>

/**
 * @file
 * A scene: what the parameters describe, built: the mesh, the body with its fixed
 * vertices, the loads, the elasticity model and the time integrator.
 */
namespace warpchol::app
{
  /**
   * Build the model of @p model's type ("linear", ...) for @p body, solved as @p solver's
   * backend says: with warpchol's factor, a peer's linear solver, or (the corotational
   * model with warp_preconditioned_cg) warp-canceling corotation that never updates,
   * solving by CG on the corotational matrix.
   */
  std::unique_ptr<fem::ElasticityModel>
  create_model(const parameters::Model &model, const fem::ElasticBody &body,
               const fem::SystemCoefficients &coefficients, const parameters::Solver &solver);

  class Scene
  {
  public:
    /** Build everything; throws InputError naming the parameter or the mesh file. */
    explicit Scene(const AllParameters &parameters);

    const AllParameters       &parameters() const;
    const fem::ElasticBody    &body() const;
    fem::ElasticityModel      &model();
    const fem::ElasticityModel &model() const;
    fem::ImplicitEuler        &integrator();
    const fem::ImplicitEuler  &integrator() const;
    const fem::Loads          &loads() const;

    /** The vertices held at rest. */
    const std::vector<unsigned int> &fixed_vertices() const;
    /** "torus (12 toroidal cells, 0 refinements)" or the mesh file's name. */
    const std::string &mesh_description() const;
    /** The order of the cells and the unknowns (Mesh/Cell order). */
    const fem::CellOrder &cell_order() const;

    /** The cuts, grasps and material changes of the parameters, for the time integrator. */
    fem::Surgery surgery() const;

    /**
     * The vertices of a region (sorted): in a box or sphere of rest positions, or by ids in
     * the mesh file's numbering. Throws InputError naming @p subsection's entries when the
     * region selects nothing or an id does not exist.
     */
    std::vector<unsigned int> select_vertices(const RegionParameters &region,
                                              const std::string      &subsection) const;

  private:
    const AllParameters                    all;
    SceneMesh                              mesh;
    std::vector<unsigned int>              fixed;
    fem::Loads                             scene_loads;
    std::unique_ptr<fem::ElasticBody>      elastic_body;
    std::unique_ptr<fem::ElasticityModel>  elasticity_model;
    std::unique_ptr<fem::ImplicitEuler>    time_integrator;
  };
} // namespace warpchol::app
