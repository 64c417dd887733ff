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
   */
  ElementMatrix warped_element_matrix(const ElasticBody &body, unsigned int e,
                                      const SystemCoefficients     &coefficients,
                                      const std::array<Matrix3, 4> &nodal_rotations,
                                      const Matrix3                &element_rotation);

  /**
   * A over the unknowns of an ElasticBody, in a deal.II SparseMatrix (the sparsity of the
   * mesh: one 3x3 block per pair of free vertices that share an element), with a copy in the
   * solver's CSC form kept up to date.
   *
   * The matrix keeps the contribution of every element, so that re-assembling a few
   * elements adds the difference of their contributions to their own entries and touches
   * nothing else: the entries of the other elements' vertices keep their values exactly,
   * and the columns that changed are those of the changed elements' vertices.
   */
  class SystemMatrix
  {
  public:
    /** Fills @p matrix with the contribution of element @p element. */
    using ElementMatrixFunction = std::function<void(unsigned int element, ElementMatrix &matrix)>;

    SystemMatrix(const ElasticBody &body, const SystemCoefficients &coefficients);

    /** A = sum over elements of @p element_matrix, plus the vertex diagonal. */
    void assemble(const ElementMatrixFunction &element_matrix);

    /**
     * Replace the contributions of @p changed_elements (sorted, unique) by
     * @p element_matrix: A changes by their differences, in their entries only. Returns the
     * columns (unknowns, sorted) whose entries changed: the dofs of the free vertices of
     * @p changed_elements.
     */
    std::vector<Index> reassemble(const std::vector<unsigned int> &changed_elements,
                                  const ElementMatrixFunction     &element_matrix);

    /** What element @p e contributes to A now. */
    const ElementMatrix &contribution(unsigned int e) const;

    const dealii::SparseMatrix<double> &matrix() const;
    /** A in CSC form with full storage, same values as matrix(). */
    const sparse::CSCMatrix &csc() const;
    Index                    size() const;

    /**
     * Write A's values and every element's contribution to a checkpoint: re-assembling A
     * would not give its values to the bit, since re-assembly adds differences.
     */
    void save(BinaryWriter &writer) const;
    /** Read what save() wrote for this body; throws InputError if the sizes differ. */
    void load(BinaryReader &reader);

  private:
    /** Entry @p k (SparsityPattern numbering) of the deal.II matrix += @p value. */
    void add_to_entry(std::int64_t k, double value);
    void set_entry(std::int64_t k, double value);
    /** Copy entry @p k of the deal.II matrix into the CSC form. */
    void copy_to_csc(std::int64_t k);

    const ElasticBody           &body;
    SystemCoefficients           coefficients;
    dealii::SparsityPattern      pattern;
    dealii::SparseMatrix<double> system_matrix;
    sparse::CSCMatrix            system_csc;

    /**
     * Per element, where entry (r, c) of its 12x12 contribution goes: the index
     * SparsityPattern::operator()(row, column) gives into the matrix' values, stored at
     * 12 c + r (Eigen's column-major order); -1 where a vertex is fixed.
     */
    std::vector<std::array<std::int64_t, 144>> element_entries;
    /** Per vertex, the indices of its 3 diagonal entries (-1 if fixed). */
    std::vector<std::array<std::int64_t, 3>> diagonal_entries;
    /** Where entry k of the deal.II matrix sits in the CSC values. */
    std::vector<Index> csc_position;
    /** The contribution of every element, as last assembled. */
    std::vector<ElementMatrix> contributions;
  };
} // namespace warpchol::fem
