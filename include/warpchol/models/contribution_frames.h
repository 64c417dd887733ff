#pragma once

#include <warpchol/base/binary_io.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/small_dense.h>
#include <warpchol/fem/system_matrix.h>

#include <array>
#include <vector>

/**
 * @file
 * The frames warp-canceling corotation's A is made in, and the rotations its factor is
 * solved with.
 */
namespace warpchol::fem
{
  /**
   * WCC solves with z = S A^-1 S^T r, where block (a, b) of element e's contribution to A is
   * T_a K_ab T_b^T (DESIGN.md section 3). Its frames are T_a = S_a^T Q_e and the solve's
   * rotations S_v = R_v P_v^T, for the rotations R_v of the vertices and Q_e of the element
   * when the element was last re-rotated, and a reference rotation P_v per vertex: A is
   * P A' P^T for the A' of reference P = I, the same preconditioner.
   *
   * An exact step takes as reference the nodal rotations of that step: every frame is then
   * the element's own rotation, T_a = Q_e, and A is the exact corotational matrix of the
   * world frame, assembled in the elements' frames like the exact path's (no frame per
   * vertex to write or read, nothing per vertex pair to rotate). The element rotations are
   * kept (one per element instead of four frames) until the element is re-rotated; the
   * reference is computed from them when a step first needs it, so that the exact path's
   * steps (ExactFallback) need no nodal rotation either.
   */
  class ContributionFrames
  {
  public:
    /** @p n_elements elements at rest: every frame and the reference the identity. */
    explicit ContributionFrames(unsigned int n_elements);

    /**
     * Every element made with @p element_rotations (T_a = Q_e) and the reference the nodal
     * rotations of the same step, @p nodal_rotations (copied), or when null computed from
     * @p element_rotations when a step first needs it (solve_rotations()).
     * @p element_rotations is referenced, not copied, until keep_rotations().
     */
    void reset(const std::vector<Matrix3> &element_rotations, const std::vector<Matrix3> *nodal_rotations);

    /**
     * Before @p element_rotations, what reset() referenced, is overwritten (the next step's
     * rotations): its values are taken, by exchange (it gets a buffer of as many rotations
     * to overwrite). Nothing to do if reset() was not called since.
     */
    void keep_rotations(std::vector<Matrix3> &element_rotations);

    /**
     * Every element made with @p frames (swapped in: a refresh made beside the steps with
     * the nodal rotations themselves), and the reference the identity.
     */
    void adopt(std::vector<std::array<Matrix3, 4>> &frames);

    /**
     * From now on S_v = R_v P_v^T with the nodal rotations @p nodal_rotations of this step
     * (@p body's; referenced, not copied): what solve_rotations() returns until the next
     * call. Computed when first asked for: an exact step, solved in the world frame, needs none.
     */
    void update_solve_rotations(const ElasticBody &body, const std::vector<Matrix3> &nodal_rotations);
    /** S of the last update_solve_rotations(): the nodal rotations themselves where P = I. */
    const std::vector<Matrix3> &solve_rotations() const;

    /** The frames T_a of element @p e. */
    std::array<Matrix3, 4> of(unsigned int e) const;

    /**
     * Element @p e (of vertices @p vertices) made from now on with the frames S_a^T Q_e:
     * with the solve rotations of this step and its rotation @p element_rotation.
     */
    void rerotate(unsigned int e, const std::array<unsigned int, 4> &vertices, const Matrix3 &element_rotation);

    /** The frames for SystemMatrix's assembly (referenced: valid until the next change). */
    ElementFrames element_frames() const;

    void save(BinaryWriter &writer) const;
    /** Read what save() wrote for as many elements; throws InputError otherwise. */
    void load(BinaryReader &reader);

  private:
    /** The frames of the elements re-rotated since the last reset() (where stored[e]). */
    std::vector<std::array<Matrix3, 4>> frames;
    std::vector<char>                   stored;
    /**
     * Q_e of the last reset(): every frame of an element not re-rotated since; those of
     * reset() itself until keep_rotations() (rotations() says which).
     */
    std::vector<Matrix3>        element_rotations;
    const std::vector<Matrix3> *referenced = nullptr;
    const std::vector<Matrix3> &rotations() const;
    /** P_v per vertex; empty: P = I. */
    mutable std::vector<Matrix3> reference;
    /** Whether the reference is still to be computed from element_rotations. */
    mutable bool reference_pending = false;
    /** The body and nodal rotations of the last update_solve_rotations(). */
    const ElasticBody          *body  = nullptr;
    const std::vector<Matrix3> *nodal = nullptr;
    /** S_v = R_v P_v^T where P is not I, computed when first asked for after an update. */
    mutable std::vector<Matrix3> relative;
    mutable bool                 relative_due = false;
  };
} // namespace warpchol::fem
