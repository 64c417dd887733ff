#pragma once

#include <warpchol/base/binary_io.h>
#include <warpchol/contact/contact.h>
#include <warpchol/contact/obstacle.h>

#include <vector>

/**
 * @file
 * Penalty contact carried by the factor (Contact/Method = penalty): a spring per contact
 * point about to enter its obstacle, held in A's diagonal as a grasp's spring is, so that
 * contacts that come and go are changes the factor takes by an update or a partial
 * refactorization.
 */
namespace warpchol::fem
{
  /**
   * The springs of penalty contact. A contact point that would be inside its obstacle at
   * the step's end, at its velocity, ties a spring of stiffness k; it keeps it while it
   * stays within the alarm distance, so that a resting contact does not tie and untie it
   * every step. The spring adds dt^2 k w to its vertices' 3 diagonal entries (w their
   * weights in the point): the same in every rotated frame. Its force is k times the
   * penetration along the normal; the implicit spring holds the point along the normal
   * and drags it along the tangents with the obstacle, a viscous friction of coefficient
   * dt k. Gaps are to where the obstacle is at the step's end (Contact::gap).
   */
  class PenaltySprings
  {
  public:
    /** The vertices whose springs' diagonal dt^2 sum k w changed, with the old and new values. */
    struct Change
    {
      std::vector<unsigned int> vertices;
      std::vector<double>       old_diagonal, new_diagonal;
    };

    /** Springs of stiffness @p stiffness (N/m), kept within @p margin (m) of their obstacle. */
    PenaltySprings(double stiffness, double margin);

    /**
     * The springs of the step from @p time among @p contacts (the step's, of a body of
     * @p n_vertices vertices at @p positions and @p velocities): those about to enter, and
     * those kept.
     */
    Change tie(const std::vector<Contact> &contacts, const std::vector<Obstacle> &obstacles,
               const std::vector<Vector3> &positions,
               const std::vector<Vector3> &velocities, unsigned int n_vertices, double time, double time_step);

    /**
     * After a solve that gave @p velocities: the @p contacts without a spring whose point
     * would end the step inside its obstacle tie one (what the step's own acceleration
     * carried in).
     */
    Change tie_entering(const std::vector<Contact> &contacts, const std::vector<Obstacle> &obstacles,
                        const std::vector<Vector3> &positions, const std::vector<Vector3> &velocities, double time,
                        double time_step);

    /** The diagonal dt^2 sum k w of the springs on @p vertex now (0 without one). */
    double diagonal(unsigned int vertex) const;

    /**
     * forces += the springs' forces for the step: k max(0, -gap) n per spring, and dt k
     * times the obstacle's tangential velocity, each spread over the point's vertices.
     */
    void add_forces(std::vector<Vector3> &forces) const;

    /**
     * The springs' forces once the step's solve gave @p velocities, added to @p forces per
     * vertex, and their totals, work and viscous friction's dissipation into @p report.
     */
    void record(const std::vector<Vector3> &velocities, double time_step, std::vector<Vector3> &forces,
                ContactStepReport &report) const;

    /** Write the springs (which the next step keeps while they stay near) and their diagonal. */
    void save(BinaryWriter &writer) const;
    /** Read what save() wrote; fails naming a spring that does not fit @p n_obstacles. */
    void load(BinaryReader &reader, std::size_t n_obstacles);

  private:
    /** Give @p contact, at @p point, a spring in the step from @p time. */
    void tie_spring(const Contact &contact, const Vector3 &point, const Obstacle &obstacle, double time,
                    double time_step);
    /** k max(0, -gap) n: what @p spring pushes along its normal at the step's start. */
    Vector3 pushing_force(const Contact &spring) const;
    /** The springs' diagonal per vertex made anew: what changed. */
    Change diagonal_change();

    double               stiffness, margin;
    double               time_step = 0;
    std::vector<Contact> springs;
    /** Per spring the velocity its drag pulls toward: its obstacle's, along the tangents. */
    std::vector<Vector3> drag_velocity;
    /** Per vertex dt^2 sum k w. */
    std::vector<double>  spring_diagonal;
  };
} // namespace warpchol::fem
