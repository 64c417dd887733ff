#include <warpchol/app/scene.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/dynamics/implicit_euler.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/models/corotational_model.h>
#include <warpchol/models/linear_model.h>
#include <warpchol/models/stiffness_warping_model.h>
#include <warpchol/models/warp_canceling_model.h>

#include <deal.II/base/multithread_info.h>

#include <algorithm>
#include <deal.II/grid/grid_tools.h>

#include <cmath>
#include <limits>

namespace warpchol::app
{
  namespace
  {
    /** The model of @p model's type, factored by warpchol or by @p peer. */
    std::unique_ptr<fem::ElasticityModel>
    create_factored_model(const parameters::Model &model, const fem::ElasticBody &body,
                          const fem::SystemCoefficients            &coefficients,
                          const cholesky::SparseCholesky::Settings &solver_settings,
                          std::unique_ptr<backends::LinearSolver>   peer = nullptr)
    {
      switch (model.type)
        {
          case fem::ModelType::linear:
            return std::make_unique<fem::LinearModel>(body, coefficients, solver_settings, std::move(peer));
          case fem::ModelType::corotational:
            return std::make_unique<fem::CorotationalModel>(body, coefficients, solver_settings, std::move(peer));
          case fem::ModelType::stiffness_warping:
            return std::make_unique<fem::StiffnessWarpingModel>(body, coefficients, solver_settings,
                                                                std::move(peer));
          case fem::ModelType::warp_canceling:
            break;
        }
      return std::make_unique<fem::WarpCancelingModel>(body, coefficients, solver_settings, model.rerotation_threshold,
                                                       model.strategy, model.target_error, std::move(peer));
    }
  } // namespace

  std::unique_ptr<fem::ElasticityModel>
  create_model(const parameters::Model &model, const fem::ElasticBody &body,
               const fem::SystemCoefficients &coefficients, const parameters::Solver &solver)
  {
    const backends::Settings &backend = solver.backend;
    if (backend.backend == backends::Backend::warp_preconditioned_cg)
      {
        // SOFA's warp preconditioner: the rest factor, never updated, in the nodal frames
        // (WCC at threshold inf), preconditions CG on the exact corotational matrix.
        parameters::Model warped      = model;
        warped.type                   = fem::ModelType::warp_canceling;
        warped.rerotation_threshold       = std::numeric_limits<double>::infinity();
        warped.target_error           = 0;
        warped.strategy.kind          = fem::StepStrategy::Kind::preconditioned;
        warped.strategy.iterate_on    = fem::StepStrategy::Target::corotational;
        warped.strategy.cg_tolerance  = backend.tolerance;
        warped.strategy.max_cg_iterations = backend.max_iterations;
        // SOFA's factor is in double precision: the lower-precision copies are warpchol's.
        cholesky::SparseCholesky::Settings settings = solver.settings;
        settings.preconditioner_precision           = cholesky::PreconditionerPrecision::full;
        return create_factored_model(warped, body, coefficients, settings);
      }
    // A peer that replaces warpchol's factor factors the rest system already.
    return create_factored_model(model, body, coefficients, solver.settings,
                                 backends::replaces_factor(backend.backend) ?
                                   backends::create_linear_solver(backend, fem::rigid_body_modes(body)) :
                                   nullptr);
  }

  std::vector<unsigned int> Scene::select_vertices(const RegionParameters &region,
                                                   const std::string      &subsection) const
  {
    return mesh.select_vertices(region, subsection);
  }

  Scene::Scene(const AllParameters &parameters)
    : all(parameters)
    , mesh(all)
  {
    // The element loops (rotations, error estimates) run on deal.II's threads: as many as
    // the solver is given. Set first: deal.II's finite element set-up does not give the
    // same last bits before and after a change of the thread limit, and two scenes with
    // the same parameters must give the same results.
    dealii::MultithreadInfo::set_thread_limit(all.solver.settings.n_threads);

    fixed = select_vertices(all.fixed_vertices.region, "Fixed vertices");
    const dealii::Triangulation<3> &triangulation = mesh.triangulation();
    elastic_body = std::make_unique<fem::ElasticBody>(triangulation, mesh.material(), all.material.mass_matrix,
                                                      mesh.marks(fixed), mesh.cell_order().unknown_order);

    scene_loads.gravity = all.gravity.acceleration;
    const auto force_vertices = select_vertices(all.region_force.region, "Region force");
    if (!force_vertices.empty() && all.region_force.total_force.norm() > 0)
      {
        // Shared in proportion to the vertices' masses, as a body force: applied to the
        // whole body it accelerates every vertex alike (a rigid translation).
        double region_mass = 0;
        for (const unsigned int v : force_vertices)
          region_mass += elastic_body->vertex_mass(v);
        scene_loads.vertex_forces.assign(triangulation.n_vertices(), fem::Vector3::Zero());
        for (const unsigned int v : force_vertices)
          scene_loads.vertex_forces[v] =
            all.region_force.total_force * (elastic_body->vertex_mass(v) / region_mass);
      }
    scene_loads.tool.vertices  = select_vertices(all.tool.region, "Tool");
    scene_loads.tool.stiffness = all.tool.spring_stiffness;
    scene_loads.tool.velocity  = all.tool.velocity;
    scene_loads.tool.duration  = all.tool.duration;
    scene_loads.tool.path      = all.tool.path.path;

    if (all.time_stepping.rest_kinetic_energy > 0 && fixed.empty() &&
        scene_loads.tool.vertices.empty() && scene_loads.has_static_load())
      throw InputError(all.file.where("Time stepping", "Rest kinetic energy") + " = " +
                       format_number(all.time_stepping.rest_kinetic_energy) +
                       ": waiting for rest needs a fixed vertex (Fixed vertices/Region) when "
                       "gravity or a region force acts: the body would fall forever");

    const fem::SystemCoefficients coefficients = fem::ImplicitEuler::coefficients(
      *elastic_body, all.time_stepping.time_step, all.time_stepping.rayleigh_mass,
      all.time_stepping.rayleigh_stiffness, scene_loads);
    elasticity_model = create_model(all.model, *elastic_body, coefficients, all.solver);
    elasticity_model->set_run_length(all.time_stepping.n_steps);
    time_integrator  = std::make_unique<fem::ImplicitEuler>(*elastic_body, *elasticity_model, scene_loads,
                                                           all.time_stepping.time_step, surgery());
    // The obstacles: each refused, at its subsection, if it starts inside the body.
    std::vector<fem::Obstacle> obstacles;
    for (const auto &parameters : all.obstacles)
      if (parameters.active())
        {
          obstacles.push_back(parameters.build());
          const std::string why = fem::obstacle_inside_body(obstacles.back(), *elastic_body, time_integrator->positions(),
                                                            all.contact.settings.tolerance);
          if (!why.empty())
            throw InputError(all.file.where(parameters.subsection, "Type") + " = " + parameters.type + ": " + why);
        }
    if (!obstacles.empty())
      time_integrator->set_contact(fem::ContactConstraints(std::move(obstacles), all.contact.settings));
    const auto &initial = all.initial_state;
    if (initial.linear_velocity.norm() > 0 || initial.angular_velocity.norm() > 0)
      time_integrator->set_initial_velocities(fem::rigid_body_velocities(
        *elastic_body, initial.linear_velocity, initial.angular_velocity));
  }

  fem::Surgery Scene::surgery() const
  {
    std::vector<fem::Blade> blades;
    for (const auto &cut : all.cuts)
      if (cut.active())
        blades.push_back(
          fem::Blade{cut.blade_start, cut.blade_end, cut.velocity, cut.start_time, cut.duration, cut.path.path});
    std::vector<fem::Grasp> grasps;
    for (const auto &grasp : all.grasps)
      if (grasp.active())
        grasps.push_back(fem::Grasp{grasp.sphere_center, grasp.sphere_radius, grasp.velocity, grasp.duration,
                                    grasp.grasp_time,    grasp.release_time,  grasp.spring_stiffness,
                                    grasp.path.path,     grasp.subsection});
    std::vector<fem::MaterialChange> material_changes;
    for (const auto &change : all.material_changes)
      if (change.region.kind != "none")
        {
          // The elements whose vertices all lie in the region.
          std::vector<bool> inside(elastic_body->n_vertices(), false);
          for (const unsigned int v : select_vertices(change.region, change.subsection))
            inside[v] = true;
          fem::MaterialChange &material_change =
            material_changes.emplace_back(fem::MaterialChange{{}, change.time, change.stiffness_factor, change.keep_stress});
          for (unsigned int e = 0; e < elastic_body->n_elements(); ++e)
            {
              const auto &vertices = elastic_body->element_vertices(e);
              if (std::all_of(vertices.begin(), vertices.end(), [&](const unsigned int v) { return inside[v]; }))
                material_change.elements.push_back(e);
            }
          if (material_change.elements.empty())
            throw InputError(all.file.where(change.subsection, "Region") +
                             ": the region holds no whole element (every vertex of one) whose material could change");
        }
    return fem::Surgery(std::move(blades), std::move(grasps), std::move(material_changes));
  }

  const AllParameters &Scene::parameters() const
  {
    return all;
  }

  const fem::ElasticBody &Scene::body() const
  {
    return *elastic_body;
  }

  fem::ElasticityModel &Scene::model()
  {
    return *elasticity_model;
  }

  const fem::ElasticityModel &Scene::model() const
  {
    return *elasticity_model;
  }

  fem::ImplicitEuler &Scene::integrator()
  {
    return *time_integrator;
  }

  const fem::ImplicitEuler &Scene::integrator() const
  {
    return *time_integrator;
  }

  const fem::Loads &Scene::loads() const
  {
    return scene_loads;
  }

  const std::vector<unsigned int> &Scene::fixed_vertices() const
  {
    return fixed;
  }

  const fem::CellOrder &Scene::cell_order() const
  {
    return mesh.cell_order();
  }

  const std::string &Scene::mesh_description() const
  {
    return mesh.description();
  }
} // namespace warpchol::app
