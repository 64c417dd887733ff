#pragma once

#include <warpchol/base/binary_io.h>
#include <warpchol/base/types.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/small_dense.h>
#include <warpchol/sparse/csc_matrix.h>

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

/**
 * @file
 * The matrix of an implicit Euler step, A = M + dt B + dt^2 K with Rayleigh damping
 * B = alpha M + beta K, that is A = (1 + dt alpha) M + (dt^2 + dt beta) K, assembled over
 * the free dofs of an ElasticBody from per-element 12x12 contributions.
 */
namespace warpchol::fem
{
  /** The scalar factors and extra diagonal that make A out of M and K. */
  struct SystemCoefficients
  {
    /** Factor of the mass matrix: 1 + dt alpha. */
    double mass = 1;
    /** Factor of the stiffness matrix: dt^2 + dt beta. */
    double stiffness = 0;
    /** The time step dt they were made for (the scale of impulses: dt times a force). */
    double time_step = 0;
    /**
     * Per vertex, a value added to the 3 diagonal entries of its free dofs (dt^2 k for the
     * springs of a pulling tool, which act along every direction alike and so stay the same
     * in every rotated frame); empty for none.
     */
    std::vector<double> vertex_diagonal;

    /** The coefficients of time step @p time_step with Rayleigh damping (alpha, beta). */
    static SystemCoefficients implicit_euler(double time_step, double rayleigh_mass,
                                             double rayleigh_stiffness);
  };

  /** c_M M_e + c_K K_e: the contribution of element @p e at rest (no rotation). */
  ElementMatrix rest_element_matrix(const ElasticBody &body, unsigned int e,
                                    const SystemCoefficients &coefficients);

  /**
   * The warped contribution of element @p e (DESIGN.md section 3):
   *   block (a, b) = c_M m_ab S_a^T S_b + c_K (S_a^T Q) K_ab (Q^T S_b)
   * with S_a = @p nodal_rotations[a] the rotations of its vertices and Q =
   * @p element_rotation. With a lumped mass, m_ab S_a^T S_b = m_a delta_ab I whatever S.
   * With every S_a = I and Q = R_e this is the exact corotated R_e K_e R_e^T.
   *
   * The reference form (dense 12x12 products with the stored K_e): SystemMatrix's
   * assembly from ElementFrames computes the same blocks without K_e.
   */
  ElementMatrix warped_element_matrix(const ElasticBody &body, unsigned int e,
                                      const SystemCoefficients     &coefficients,
                                      const std::array<Matrix3, 4> &nodal_rotations,
                                      const Matrix3                &element_rotation);

  /**
   * The frames the elements' contributions to A are made in: block (a, b) of element e is
   *   c_K T_a K_ab T_b^T + c_M m_ab T_a T_b^T,   T_a = S_a^T Q_e
   * (warped_element_matrix() with the frames T_a of its vertices). Three cases: at rest
   * (every T_a = I), rotated (every T_a = R_e, exact corotation) and warped (four frames
   * per element, warp-canceling corotation's stored ones, or where an element has none
   * stored, its rotation for all four). The vectors are referenced, not copied: they must
   * outlive the assembly.
   */
  struct ElementFrames
  {
    enum class Kind
    {
      rest,
      rotated,
      warped
    };
    Kind                                      kind              = Kind::rest;
    const std::vector<Matrix3>                *element_rotations = nullptr;
    const std::vector<std::array<Matrix3, 4>> *vertex_frames     = nullptr;
    /** warped: where null or nonzero, element e has vertex_frames[e]; else element_rotations[e]. */
    const std::vector<char>                   *frames_stored     = nullptr;

    static ElementFrames rest();
    /** T_a = @p rotations[e] for the four vertices of element e. */
    static ElementFrames rotated(const std::vector<Matrix3> &rotations);
    /** T_a = @p frames[e][a]. */
    static ElementFrames warped(const std::vector<std::array<Matrix3, 4>> &frames);
    /** T_a = @p frames[e][a] where @p stored[e], else @p rotations[e]. */
    static ElementFrames rerotated(const std::vector<std::array<Matrix3, 4>> &frames,
                                   const std::vector<char> &stored, const std::vector<Matrix3> &rotations);
  };

  /**
   * A over the unknowns of an ElasticBody, stored as the lower triangle in CSC form (the
   * form the solver reads), assembled from the contributions of the elements; the full
   * CSC form and a deal.II SparseMatrix are made from it on request (the peers read them).
   *
   * Assembly is a scatter computed once: the pattern is that of the mesh (one 3x3 block per
   * pair of free vertices that share an element), and each of the 10 blocks (a >= b) of an
   * element's symmetric contribution has its place in the values found at construction.
   * From ElementFrames the blocks are formed without K_e, from the shape function gradients
   * g_a of the element (constant on a linear tet):
   *   T_a K_ab T_b^T = V (lambda (T_a g_a)(T_b g_b)^T + mu (T_a g_b)(T_b g_a)^T + mu (g_a.g_b) T_a T_b^T)
   * eight elements side by side in SIMD lanes, about 250 multiply-adds and 78 stores per
   * element instead of 864 multiply-adds with the 1152 bytes of K_e.
   *
   * Every entry is the sum of its elements' contributions in increasing element order,
   * then the vertex diagonal: whatever the threads (they own ranges of columns, and an
   * element at the border of two ranges is formed by both) and whether all columns or a
   * few are assembled. Re-assembling the columns of some vertices therefore gives every
   * other entry the bits a full assembly would give it: a partial refactorization sees
   * exactly the columns that changed, and nothing drifts over the steps.
   */
  class SystemMatrix
  {
  public:
    /** Fills @p matrix with the contribution of element @p element. */
    using ElementMatrixFunction = std::function<void(unsigned int element, ElementMatrix &matrix)>;

    SystemMatrix(const ElasticBody &body, const SystemCoefficients &coefficients);

    /** A = sum over elements of their contributions in @p frames, plus the vertex diagonal. */
    void assemble(const ElementFrames &frames);

    /**
     * The contributions of @p changed_elements (sorted, unique) are now those of
     * @p frames (the others' must be unchanged): re-assemble the columns of their
     * vertices, or all of A where that is cheaper (the same values). Returns the unknowns
     * (sorted) whose columns changed: the dofs of the free vertices of @p changed_elements.
     */
    std::vector<Index> reassemble(const std::vector<unsigned int> &changed_elements,
                                  const ElementFrames             &frames);

    /**
     * Re-assemble the columns of @p vertices (those that are free; in any order) from the
     * contributions in @p frames and the vertex diagonal: what a change of a vertex's
     * diagonal (set_vertex_diagonal(): a grasp) or of an element's material (a cut, a
     * material change: then the columns of all its vertices) needs. Returns the unknowns
     * (sorted) of those columns.
     */
    std::vector<Index> reassemble_vertices(const std::vector<unsigned int> &vertices, const ElementFrames &frames);

    /**
     * From now on add @p value to the 3 diagonal entries of @p vertex (a spring that ties it
     * to an instrument, a free particle's mass): A changes where its columns are next
     * assembled (reassemble_vertices()).
     */
    void set_vertex_diagonal(unsigned int vertex, double value);

    /**
     * The same with any element matrix (the reference path: dense 12x12 matrices from a
     * function, one element at a time, the blocks of the lower triangle scattered alike).
     * @p element_matrix must be symmetric.
     */
    void assemble(const ElementMatrixFunction &element_matrix);
    std::vector<Index> reassemble(const std::vector<unsigned int> &changed_elements,
                                  const ElementMatrixFunction     &element_matrix);

    /**
     * Assemble on @p n_threads threads from now on; 0 (the default): as many as deal.II's
     * MultithreadInfo allows. A copy assembling beside the steps takes one.
     */
    void set_thread_count(unsigned int n_threads);

    /** Exchange A's values with those of @p other, a matrix of the same body. */
    void swap_values(SystemMatrix &other);

    /**
     * How many times A's values changed other than in the columns that reassemble() and
     * reassemble_vertices() return: assemblies of all of A, swap_values(), load(). A caller
     * that finds the same count as at its last look knows the columns those returned since
     * are all that changed (cholesky::ChangeListing::complete).
     */
    std::uint64_t n_whole_changes() const;

    /** A's lower triangle (unknown numbering): what the solver factors. */
    const sparse::CSCMatrix &lower() const;
    /** A in CSC form with full storage, same values (made from lower() when asked). */
    const sparse::CSCMatrix &csc() const;
    /** A as a deal.II SparseMatrix (the sparsity of the mesh), made from lower() when asked. */
    const dealii::SparseMatrix<double> &matrix() const;
    Index                               size() const;

    /**
     * Write A's values to a checkpoint: a partly re-assembled A is not what a full
     * assembly at the last rotations would give.
     */
    void save(BinaryWriter &writer) const;
    /** Read what save() wrote for this body; throws InputError if the sizes differ. */
    void load(BinaryReader &reader);

  private:
    /** Where the blocks of one element go. */
    struct ElementScatter
    {
      /**
       * Block k = a (a + 1) / 2 + b (a >= b): the position in the values of its entry
       * (0, 0) in the column vertex's first column, -1 if a vertex is fixed.
       */
      std::array<std::int32_t, 10> position;
      /**
       * Per vertex, the stride 3 n + 2 of its columns (0 if fixed): a block's second column
       * starts that far after its first, in the columns of its vertex of smaller unknown.
       */
      std::array<std::int32_t, 4> stride;
      /** The free index of each vertex (-1: fixed); block k lands in the columns of the smaller. */
      std::array<std::int32_t, 4> free_vertex;
    };

    /** A range of free vertices whose columns one task assembles, and the elements that touch it. */
    struct ColumnRange
    {
      Index                     first_vertex = 0;
      Index                     end_vertex   = 0;
      std::vector<unsigned int> elements;
    };

    /**
     * Assemble the columns of the free vertices (free index) in [range.first_vertex,
     * range.end_vertex) for which @p column_selected is true (all if null) from
     * @p elements (sorted): zero them, add the blocks of the elements, then the diagonal.
     */
    template <typename BlockSource>
    void assemble_range(const ColumnRange &range, const std::vector<unsigned int> &elements,
                        const std::vector<char> *column_selected, const BlockSource &blocks);

    /** The free vertices (free index, sorted) of @p changed_elements. */
    std::vector<Index> touched_free_vertices(const std::vector<unsigned int> &changed_elements) const;
    /** Re-assemble the columns of the free vertices @p touched (free index, sorted, unique). */
    std::vector<Index> reassemble_free_vertices(const std::vector<Index> &touched, const ElementFrames &frames);
    /** The unknowns of @p free_vertices. */
    static std::vector<Index> columns_of(const std::vector<Index> &free_vertices);

    /**
     * Run @p assemble on every column range for the threads deal.II allows now (one range
     * holding every column and element for one thread), the ranges on threads.
     */
    void for_each_range(const std::function<void(const ColumnRange &)> &assemble);

    /** The free index (first unknown / 3) of @p vertex, -1 for a fixed one. */
    Index free_index(unsigned int vertex) const;

    const ElasticBody           &body;
    SystemCoefficients           coefficients;
    sparse::CSCMatrix            lower_matrix;
    std::uint64_t                whole_changes = 0;
    std::vector<ElementScatter>  scatter;
    /**
     * Per element, bit k: block k lands as its transpose (its row vertex a has the smaller
     * unknown). The blocks are formed so (form_blocks()): the scatter adds every block
     * alike, with no branch on a bit that changes from one element to the next.
     */
    std::vector<std::uint16_t> transposed_blocks;
    /** One range of every column and element: the serial assembly and the reference path. */
    ColumnRange                  whole;
    /** The ranges of the threaded assembly, made for ranges_threads threads. */
    std::vector<ColumnRange>     ranges;
    unsigned int                 ranges_threads = 0;
    /** set_thread_count(): 0 for deal.II's number. */
    unsigned int                 thread_count = 0;

    /** The forms made on request, and where their entries come from in lower(). */
    mutable sparse::CSCMatrix                             full_matrix;
    mutable std::vector<std::int64_t>                     full_source;
    mutable dealii::SparsityPattern                       pattern;
    mutable dealii::SparseMatrix<double>                  dealii_matrix;
    mutable std::vector<std::int64_t>                     dealii_source;
    mutable bool                                          full_current   = false;
    mutable bool                                          dealii_current = false;
  };
} // namespace warpchol::fem
