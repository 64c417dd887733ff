#pragma once

#include <warpchol/base/binary_io.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/small_dense.h>
#include <warpchol/models/elasticity_model.h>
#include <warpchol/surgery/blade.h>
#include <warpchol/surgery/instrument_path.h>

#include <limits>
#include <string>
#include <vector>

/**
 * @file
 * Local changes of the body and of its boundary conditions during a run: cuts, grasps and
 * changes of the material (issue 19), each marking the elements or vertices whose columns
 * of A change.
 */
namespace warpchol::fem
{
  /**
   * A grasping instrument: its jaws, a sphere of @p radius around @p centre, close at
   * @p grasp_time on the free vertices within them (at their positions then), move with
   * @p velocity for @p duration and open at @p release_time. Each grasped vertex is tied to
   * its place in the jaws by a spring of @p stiffness (N/m), or, for 0, a penalty spring of
   * 1e6 m_v / dt^2 (m_v its mass), which holds it there within a millionth of the motion:
   * the grasp changes the diagonal of A at the grasped vertices only (a constraint would
   * remove unknowns or change the columns of their neighbours too).
   *
   * With a @p path (values: the jaws' centre), the jaws follow it instead: they close
   * around its position at grasp_time and move as it does.
   */
  struct Grasp
  {
    Vector3        centre       = Vector3::Zero();
    double         radius       = 0;
    Vector3        velocity     = Vector3::Zero();
    double         duration     = 0;
    double         grasp_time   = 0;
    double         release_time = std::numeric_limits<double>::infinity();
    double         stiffness    = 0;
    InstrumentPath path;
    /** What the messages call it: "Grasp", "Grasp 2", ... */
    std::string    name = "Grasp";

    /** The centre of the jaws when they close. */
    Vector3 closing_centre() const;
    /** How far the jaws have moved at time @p time since they closed. */
    Vector3 offset(double time) const;
  };

  /**
   * At @p time the stiffness of @p elements is multiplied by @p factor (> 0). With
   * @p keep_stress their stress is unchanged at the change (a plastic strain takes up the
   * rest, ElasticBody::scale_element_stiffness_keeping_stress()); without, they keep their
   * rest shape and their stress is multiplied by @p factor.
   */
  struct MaterialChange
  {
    std::vector<unsigned int> elements;
    double                    time        = 0;
    double                    factor      = 1;
    bool                      keep_stress = true;
  };

  /**
   * The energy the changes of the body put in (> 0) or took out (< 0) so far, each
   * counted at its step as the energy held after it minus before it, at the same positions
   * and velocities: a material change, the changed elements' elastic energy; a cut, the
   * removed elements' elastic energy and the kinetic energy of the mass they took along;
   * a grasp or a release, the springs' energy.
   */
  struct ChangeEnergy
  {
    double material_changes = 0;
    double cuts             = 0;
    double grasps           = 0;

    double total() const;
  };

  /**
   * What happens to the body during a run besides the loads: blades that cut, grasps,
   * changes of the material, any number of each (issue 27), each at its own times. Within
   * a step the cuts come first, then the material changes, then the grasps, each kind in
   * its order; a vertex two grasps hold is tied to both. Before each step, changes_of_step() applies to the body
   * what happens in the step and returns what changed in A for the model
   * (ElasticityModel::apply_change()); the springs of the grasp act through
   * add_spring_forces() and spring_diagonal() as the tool's do.
   */
  class Surgery
  {
  public:
    Surgery() = default;
    Surgery(std::vector<Blade> blades, std::vector<Grasp> grasps, std::vector<MaterialChange> material_changes);

    /** Whether anything happens at all. */
    bool active() const;

    /**
     * Apply to @p body what happens during the step from @p time to @p time + @p time_step
     * (step number @p step), with the body at @p positions and @p velocities: the elements
     * the blade crosses are cut, the jaws close or open, the material changes; the energy
     * each puts in or takes out is added to change_energy(), its elastic part with the
     * element rotations if @p rotated (the model's, ElasticityModel::uses_rotations()).
     * @p tool_diagonal is what the tool's springs add to each vertex's diagonal (dt^2 k;
     * empty for none). Counts what it did in @p statistics (elements_cut,
     * vertices_grasped, vertices_released, elements_changed). Throws InputError when the
     * jaws close on no free vertex.
     */
    SystemChange changes_of_step(ElasticBody &body, const std::vector<Vector3> &positions,
                                 const std::vector<Vector3> &velocities, bool rotated, unsigned int step,
                                 double time, double time_step, const std::vector<double> &tool_diagonal,
                                 StepStatistics &statistics);

    /** The energy the changes put in or took out so far (the energy balance counts it). */
    const ChangeEnergy &change_energy() const;

    /**
     * What was to happen but never did, the steps so far having ended before its time
     * ("the material change at 0.5 s", "the cut from 0.4 s", "the grasp at 0.6 s"): for
     * the summary's warning, since a time past the run's end is silently nothing.
     */
    std::vector<std::string> events_not_reached() const;

    /** forces[v] += k (target(@p time) - x_v) for each grasped vertex v. */
    void add_spring_forces(const std::vector<Vector3> &positions, double time, std::vector<Vector3> &forces) const;
    /** The grasp springs' energy at @p positions and @p time: sum of 1/2 k |target - x|^2. */
    double spring_energy(const std::vector<Vector3> &positions, double time) const;
    /**
     * The energy the moving jaws put into the springs between @p from and @p to at
     * @p positions, and the springs' work on the body over the step that moved it from
     * @p old_positions to @p new_positions (as ImplicitEuler counts the tool's).
     */
    double spring_work(const std::vector<Vector3> &positions, double from, double to) const;
    double spring_work_on_body(const std::vector<Vector3> &old_positions, const std::vector<Vector3> &new_positions,
                               double time) const;

    /** Per element, the step it was cut at; -1 if it is not. */
    const std::vector<int> &cut_steps() const;
    /** Per vertex, 1 while it is grasped. */
    std::vector<char> grasped_vertices(unsigned int n_vertices) const;
    /** Elements cut so far. */
    unsigned int n_cut() const;

    /** Write what happened so far (the body's own state is ElasticBody's to write). */
    void save(BinaryWriter &writer) const;
    void load(BinaryReader &reader);

  private:
    /** What one grasp holds. */
    struct Hold
    {
      /** The grasped vertices, their places in the jaws when they closed, their springs (N/m). */
      std::vector<unsigned int> held;
      std::vector<Vector3>      anchors;
      std::vector<double>       stiffness;
      bool                      closed   = false;
      bool                      released = false;
    };

    std::vector<Blade>          blades;
    std::vector<Grasp>          grasps;
    std::vector<MaterialChange> material_changes;
    /** Per material change, whether it happened. */
    std::vector<bool>           material_changed;
    std::vector<int>            cut_step;
    /** Per grasp. */
    std::vector<Hold>           holds;
    /** The end of the last step applied so far. */
    double                      reached_time = 0;
    ChangeEnergy                energy_of_changes;

    /** changes_of_step()'s parts, in its order: the blades' cuts, the materials' changes, the grasps. */
    void cut_elements(ElasticBody &body, const std::vector<Vector3> &positions, const std::vector<Vector3> &velocities,
                      bool rotated, unsigned int step, double time, double time_step, SystemChange &change,
                      StepStatistics &statistics);
    void change_materials(ElasticBody &body, const std::vector<Vector3> &positions, bool rotated, double time,
                          double time_step, SystemChange &change, StepStatistics &statistics);
    /** The jaws that close or open in the step; the springs' diagonals of the vertices they change. */
    void grasp_and_release(ElasticBody &body, const std::vector<Vector3> &positions, double time, double time_step,
                           const std::vector<double> &tool_diagonal, SystemChange &change,
                           StepStatistics &statistics);

    void save_hold(BinaryWriter &writer, const Hold &hold) const;
    void load_hold(BinaryReader &reader, Hold &hold);
  };
} // namespace warpchol::fem
