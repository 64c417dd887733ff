#pragma once

#include <warpchol/base/binary_io.h>
#include <warpchol/base/types.h>
#include <warpchol/fem/rotations.h>
#include <warpchol/fem/small_dense.h>

#include <deal.II/base/array_view.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/grid/tria.h>

#include <Eigen/Core>

#include <array>
#include <vector>

/**
 * @file
 * A linear elastic body meshed with tetrahedra: its rest geometry, the rest stiffness and
 * mass of every element, and what depends on a deformed configuration (element and nodal
 * rotations, corotated elastic forces, energies).
 */
namespace warpchol::fem
{
  /** Isotropic linear elastic material. */
  struct Material
  {
    /** Young's modulus E (Pa), > 0. */
    double youngs_modulus = 50;
    /** Poisson's ratio nu, in (-1, 0.5). */
    double poisson_ratio = 0.45;
    /** Mass density (kg/m^3), > 0. */
    double density = 20;

    /** Lame's first parameter lambda = E nu / ((1 + nu)(1 - 2 nu)). */
    double lame_lambda() const;
    /** The shear modulus mu = E / (2 (1 + nu)). */
    double lame_mu() const;
  };

  /** How the mass matrix is built. */
  enum class MassMatrix
  {
    /** Row sums on the diagonal: one mass per vertex, invariant under rotations. */
    lumped,
    /** The Galerkin mass matrix of the linear elements. */
    consistent
  };

  /**
   * The body: a deal.II Triangulation<3> of tetrahedra with the vector-valued linear
   * element FESystem(FE_SimplexP<3>(1), 3).
   *
   * Numbering. Vertex v is the triangulation's vertex v; element e is the active cell with
   * active_cell_index() e, and its local vertex a is the cell's vertex a. The DoFHandler is
   * renumbered so that the dof of component c at vertex v is 3 v + c: a vector of per-vertex
   * 3-vectors is then a dof vector. The linear systems are posed on the *unknowns*, the
   * dofs of the vertices that are not fixed, numbered 3 k + c for the k-th free vertex, in
   * vertex order or in the order given (a locality order: fem::order_cells_for_locality()).
   *
   * Element matrices are 12x12 with rows 3 a + c (see small_dense.h): K_e, the rest
   * stiffness of isotropic linear elasticity, and the mass, stored as the 4x4 scalar matrix
   * m_ab (the 12x12 mass is m_ab times the 3x3 identity in block (a, b)).
   */
  class ElasticBody
  {
  public:
    /**
     * Set the body up on @p triangulation (which must outlive it, hold only tetrahedra and
     * use every vertex). @p fixed_vertex[v] is true for the vertices held at rest.
     * @p unknown_order lists every vertex once, in the order the free ones get their
     * unknowns (empty: vertex order).
     * Throws InputError naming the cell when an element has no volume.
     */
    ElasticBody(const dealii::Triangulation<3> &triangulation, const Material &material,
                MassMatrix mass_matrix, const std::vector<bool> &fixed_vertex,
                const std::vector<unsigned int> &unknown_order = {});

    unsigned int n_vertices() const;
    unsigned int n_elements() const;
    /** Number of free dofs: 3 per vertex that is not fixed. */
    Index n_unknowns() const;

    /** The global vertices of element @p e, in the order of the element matrices. */
    const std::array<unsigned int, 4> &element_vertices(unsigned int e) const;
    /** The elements that contain vertex @p v, in increasing order. */
    dealii::ArrayView<const unsigned int> elements_of_vertex(unsigned int v) const;
    /** The first of the 3 unknowns of vertex @p v, or -1 when it is fixed. */
    Index first_unknown(unsigned int v) const
    {
      return first_unknown_of_vertex[v];
    }
    /** The vertex whose dofs hold unknown @p unknown (3 k + c is vertex of k, component c). */
    unsigned int vertex_of_unknown(Index unknown) const;
    bool  is_fixed(unsigned int v) const;

    const std::vector<Vector3> &rest_positions() const;
    double                      element_volume(unsigned int e) const
    {
      return rest_volumes[e];
    }
    double                      total_volume() const;
    double                      total_mass() const;

    const Material &material() const;
    MassMatrix      mass_matrix_type() const;

    /**
     * Dm^-1 of element @p e, the inverse of its rest edge matrix [X1 - X0, X2 - X0, X3 - X0]:
     * row a - 1 is the gradient of the shape function of its vertex a (a = 1, 2, 3; vertex
     * 0's is minus their sum), constant on the element.
     */
    const Matrix3 &rest_shape_gradients(unsigned int e) const
    {
      return inverse_rest_edges[e];
    }

    /** Lame's first parameter and the shear modulus of the material. */
    double lame_lambda() const;
    double lame_mu() const;

    /** K_e: the rest stiffness matrix of element @p e. */
    const ElementMatrix &rest_stiffness(unsigned int e) const;
    /** m_ab: the scalar mass matrix of element @p e (consistent, or lumped: diagonal). */
    const Eigen::Matrix4d &element_mass(unsigned int e) const
    {
      return mass[e];
    }
    /**
     * m_aa, the diagonal of element_mass(): the whole of a lumped mass, in 32 bytes where
     * element_mass() takes 128 (the assembly of A reads it per element).
     */
    const std::array<double, 4> &element_mass_diagonal(unsigned int e) const
    {
      return mass_diagonal[e];
    }
    /**
     * The lumped mass of vertex @p v (the row sum of the consistent mass matrix over its
     * elements; a free particle's, see cut_element()).
     */
    double vertex_mass(unsigned int v) const;

    /**
     * @name Changes of the body (surgery)
     * A cut element leaves the body: its stiffness and its mass (the test: the body then
     * moves as a mesh built without it). A vertex that a cut leaves in no element keeps the
     * mass it had as a free particle: it falls freely, A keeps its rank, and the pattern of
     * A and the structure of its factor stay (an entry that becomes zero stays stored).
     * The models read the new state where they assemble or apply the elements; they must be
     * told which elements changed (ElasticityModel::apply_change()).
     */
    /** @{ */
    /** Cut element @p e (once); returns the vertices it leaves in no element. */
    std::vector<unsigned int> cut_element(unsigned int e);
    /**
     * Multiply the stiffness (Young's modulus) of element @p e by @p factor > 0. Its rest
     * shape stays: a strained element's stress is multiplied by @p factor too.
     */
    void scale_element_stiffness(unsigned int e, double factor);
    /**
     * The same, keeping element @p e's stress at the displacement gradient
     * @p displacement_gradient (displacement_gradient(): G = R_e^T F - I in its frame):
     * its plastic strain eps_p moves to eps - (eps - eps_p) / @p factor, eps = sym(G), so
     * that the new stiffness gives the old stress (issue 29). Stiffened tissue then resists
     * further deformation from where it is instead of springing back to its rest shape;
     * its elastic energy is divided by @p factor.
     */
    void scale_element_stiffness_keeping_stress(unsigned int e, double factor, const Matrix3 &displacement_gradient);
    /** The plastic strain of element @p e in its frame: zero unless a change kept its stress. */
    Matrix3 plastic_strain(unsigned int e) const;
    bool   element_is_cut(unsigned int e) const;
    /** The factor of element @p e's stiffness: 1 as built, 0 once cut. */
    double element_stiffness_scale(unsigned int e) const
    {
      return stiffness_scale[e];
    }
    /**
     * The weight of element @p e's stiffness in every kernel: its volume times its
     * stiffness scale (0 once cut).
     */
    double element_stiffness_weight(unsigned int e) const
    {
      return volumes[e];
    }
    /** The mass vertex @p v holds as a free particle (in no element any more); 0 otherwise. */
    double free_particle_mass(unsigned int v) const
    {
      return particle_mass[v];
    }
    /** Write the changes to a checkpoint (cuts, stiffness scales, the masses they moved). */
    void save_changes(BinaryWriter &writer) const;
    /** Read what save_changes() wrote, into a body built from the same mesh. */
    void load_changes(BinaryReader &reader);
    /** @} */

    /** F = Ds Dm^-1 of element @p e: deformed edge vectors times inverse rest edge vectors. */
    Matrix3 deformation_gradient(unsigned int e, const std::vector<Vector3> &positions) const;

    /**
     * G = R^T F - I of element @p e at @p positions, the displacement gradient in its frame
     * that the element kernels take: R the rotation of F (rotations_of(), the bits of
     * evaluate()'s) if @p rotated, the identity if not (the linear model).
     */
    Matrix3 displacement_gradient(unsigned int e, const std::vector<Vector3> &positions, bool rotated) const;

    /**
     * The elastic energy V/2 sigma : (eps - eps_p) of element @p e at the displacement
     * gradient @p displacement_gradient, with its stiffness scale and plastic strain.
     */
    double element_energy(unsigned int e, const Matrix3 &displacement_gradient) const;

    /**
     * The nodal forces K_e u_e of element @p e for a displacement u_e whose gradient (in
     * the element's frame, constant on a linear tet) is @p displacement_gradient,
     * computed without K_e: the strain eps = sym(G), the stress
     * sigma = lambda tr(eps) I + 2 mu eps, and vertex a's force V sigma grad N_a. Column
     * a - 1 of the result is vertex a's force (a = 1, 2, 3); vertex 0's is minus their sum.
     * About 60 flops instead of the 144 multiply-adds (and 1152 bytes read) of K_e u_e.
     */
    Matrix3 stiffness_forces(unsigned int e, const Matrix3 &displacement_gradient) const;

    /** The gradient of a per-vertex field (linear on element @p e): [f1-f0, f2-f0, f3-f0] Dm^-1. */
    Matrix3 field_gradient(unsigned int e, const std::vector<Vector3> &field) const;
    /** The same for the values @p vertex_values at the element's 4 vertices. */
    Matrix3 field_gradient(unsigned int e, const std::array<Vector3, 4> &vertex_values) const;

    /** Which rotations evaluate() computes. */
    enum class Rotations
    {
      /** None: R_e = I (the linear model). */
      none,
      /** The element rotations R_e. */
      elements,
      /** R_e and the nodal rotations S_i. */
      elements_and_vertices
    };

    /**
     * Work arrays of the sums of the elements' forces on their vertices on threads: the
     * forces of the elements at range borders, and each range's sums.
     */
    struct ForceWork
    {
      std::vector<Matrix3>              shared_forces;
      std::vector<std::vector<Vector3>> range_sums;
    };

    /** What evaluate() computes for one configuration. */
    struct State
    {
      /** R_e per element (empty for Rotations::none). */
      std::vector<Matrix3> element_rotations;
      /** S_i per vertex (empty unless asked for). */
      std::vector<Matrix3> nodal_rotations;
      /** The elastic force on each vertex: the sum of -R_e K_e (R_e^T x_e - X_e) over its elements. */
      std::vector<Vector3> forces;
      /** Per element, the norm of its 12 nodal forces. */
      std::vector<double> element_force_norms;
      /** Sum over elements of 1/2 u_e^T K_e u_e, u_e = R_e^T x_e - X_e. */
      double elastic_energy = 0;
      /** Work arrays of the sums of the forces. */
      ForceWork force_work;
      /** The paths the element rotations took (rotations_of()). */
      RotationPaths rotation_paths;
    };

    /**
     * One fused pass over the elements at @p positions: for each element F, its rotation
     * R_e (rotation_of(), unless @p rotations is none), its corotated force
     * -R_e K_e (R_e^T x_e - X_e) (matrix-free, stiffness_forces() of G = R_e^T F - I) and
     * its energy; then one pass over the vertices that sums the forces of their elements
     * (in element order, so the result does not depend on the threads) and, if asked,
     * computes the nodal rotations. Both passes run on deal.II's (TBB) threads.
     */
    void evaluate(const std::vector<Vector3> &positions, Rotations rotations, State &state) const;

    /** R_e for every element: the rotation of the polar decomposition of F (rotations.h). */
    void compute_element_rotations(const std::vector<Vector3> &positions,
                                   std::vector<Matrix3>       &element_rotations) const;

    /**
     * S_i for every vertex: the volume-weighted average of the rotations of the elements
     * around vertex i, projected back onto the rotations by a polar decomposition.
     */
    void compute_nodal_rotations(const std::vector<Matrix3> &element_rotations,
                                 std::vector<Matrix3>       &nodal_rotations) const;

    /**
     * forces += the elastic forces at @p positions: f_e = -R_e K_e (R_e^T x_e - X_e) for
     * every element, or -K_e (x_e - X_e) when @p element_rotations is null (linear).
     */
    void add_elastic_forces(const std::vector<Vector3> &positions,
                            const std::vector<Matrix3> *element_rotations,
                            std::vector<Vector3>       &forces) const;

    /** Sum over elements of 1/2 u_e^T K_e u_e, u_e = R_e^T x_e - X_e (R_e = I if null). */
    double elastic_energy(const std::vector<Vector3> &positions,
                          const std::vector<Matrix3> *element_rotations) const;

    /** Per element, 1/2 u_e^T K_e u_e, u_e = R_e^T x_e - X_e (R_e = I if null). */
    std::vector<double> element_energies(const std::vector<Vector3> &positions,
                                         const std::vector<Matrix3> *element_rotations) const;

    /**
     * out = K^ v with K^ = sum over elements of R_e K_e R_e^T (K_e alone when
     * @p element_rotations is null): the corotated stiffness applied without forming it,
     * on threads, the result independent of their number; @p work is a work array.
     */
    void corotated_stiffness_times(const std::vector<Matrix3> *element_rotations, const std::vector<Vector3> &v,
                                   std::vector<Vector3> &out, ForceWork &work) const;

    /** out += M v (the mass matrix of the chosen type). */
    void add_mass_times(const std::vector<Vector3> &velocities, std::vector<Vector3> &out) const;

    /** 1/2 v^T M v. */
    double kinetic_energy(const std::vector<Vector3> &velocities) const;

    const dealii::Triangulation<3> &triangulation() const;
    /** The DoFHandler, numbered 3 v + c (see the class documentation). */
    const dealii::DoFHandler<3> &dof_handler() const;
    const dealii::Mapping<3>    &mapping() const;

  private:
    /**
     * first_unknown_of_vertex and free_vertices: the free vertices get consecutive unknowns,
     * in vertex order or in @p unknown_order (checked to list every vertex once).
     */
    void number_free_vertices(const std::vector<bool> &fixed_vertex, const std::vector<unsigned int> &unknown_order);
    /** vertices_of_element, the elements around each vertex (around_*) and their span. */
    void list_elements_around_vertices();
    void compute_element_matrices();

    /** sigma = lambda tr(eps) I + 2 mu eps with eps = sym(@p displacement_gradient). */
    Matrix3 stress(const Matrix3 &displacement_gradient) const;

    /**
     * The fused element pass over every element, on the threads deal.II allows and the SIMD
     * target chosen at run time, with @p field the positions (or, for a @p product, the
     * field the corotated stiffness multiplies): per element F, its rotation (computed into
     * @p computed_rotations if not null, else @p given_rotations, else I), the world forces
     * (a product's: R K_e R^T field_e, no plastic strain), and where not null the energies
     * and force norms; the rotations' paths added to @p paths if not null.
     *
     * The forces are summed on the vertices: @p vertex_forces (zero on entry) gets at v the
     * sum over v's elements, in element order (the bits do not depend on the threads). Each
     * thread takes a range of elements and adds an element's forces to the vertices whose
     * elements all lie in its range as soon as it has them (into sums of its own in
     * @p work), not through an array of every element's forces written and read back (144
     * bytes per element from memory on a large body); the forces of the elements around a
     * vertex two ranges share are kept in @p work and summed after the ranges.
     */
    void fused_pass(const std::vector<Vector3> &field, const std::vector<Matrix3> *given_rotations, bool product,
                    Matrix3 *computed_rotations, std::vector<Vector3> &vertex_forces, double *energies,
                    double *force_norms, RotationPaths *paths, ForceWork &work) const;

    /** The forces on the vertices and each element's energy at @p positions for the given rotations (I if null). */
    void forces_at_given_rotations(const std::vector<Vector3> &positions, const std::vector<Matrix3> *element_rotations,
                                   std::vector<Vector3> &vertex_forces, std::vector<double> &energies) const;

    const dealii::Triangulation<3> &tria;
    Material                        body_material;
    /** Lame's parameters of the material, for the element kernels. */
    double                          lambda = 0;
    double                          mu     = 0;
    MassMatrix                      mass_type;
    dealii::FESystem<3>             fe;
    dealii::MappingFE<3>            fe_mapping;
    dealii::DoFHandler<3>           dofs;

    std::vector<std::array<unsigned int, 4>> vertices_of_element;
    /**
     * The elements around each vertex, in increasing order, in one array (small vectors
     * would cost the gather of the forces a pointer each): those of v at
     * [around_start[v], around_start[v + 1]), with v's local index (0..3) in each.
     */
    std::vector<unsigned int>                around_start, around_element;
    std::vector<unsigned char>               around_local;
    /** The first and last element around each vertex: whether one range of elements holds them all. */
    std::vector<std::array<unsigned int, 2>> element_span;
    std::vector<Index>                       first_unknown_of_vertex;
    std::vector<unsigned int>                free_vertices;
    Index                                    unknown_count = 0;
    std::vector<Vector3>                     rest;
    /**
     * Per element, its volume times its stiffness scale: the weight of its stiffness in
     * every kernel (forces, products, estimates) and of its rotation in the nodal ones.
     */
    std::vector<double>                      volumes;
    /** Per element, its volume as built. */
    std::vector<double>                      rest_volumes;
    std::vector<double>                      stiffness_scale;
    /**
     * Per element, its plastic strain in its frame (scale_element_stiffness_keeping_stress());
     * empty while every one is zero, so that the kernels skip it.
     */
    std::vector<Matrix3>                     plastic_strains;
    std::vector<bool>                        cut;
    /** Per vertex, its elements that are not cut. */
    std::vector<unsigned int>                live_elements;
    std::vector<double>                      particle_mass;
    std::vector<Matrix3>                     inverse_rest_edges;
    std::vector<ElementMatrix>               stiffness;
    std::vector<Eigen::Matrix4d>             mass;
    std::vector<std::array<double, 4>>       mass_diagonal;
    std::vector<double>                      lumped_mass;
  };
} // namespace warpchol::fem
