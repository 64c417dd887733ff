#pragma once

#include <warpchol/base/types.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/sparse/csc_matrix.h>
#include <warpchol/sparse/dealii_conversion.h>

#include <deal.II/base/config.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/subscriptor.h>
#include <deal.II/base/types.h>

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#ifdef DEAL_II_WITH_TRILINOS
#  include <deal.II/lac/trilinos_sparse_matrix.h>
#  include <deal.II/lac/trilinos_vector.h>
#endif

#include <string>
#include <vector>

/**
 * @file
 * warpchol's solver for deal.II programs: the interface of deal.II's SparseDirectUMFPACK
 * over cholesky::SparseCholesky, with a partial refactorization.
 */
namespace warpchol
{
  /**
   * A sparse direct solver for symmetric positive definite matrices, A = P L L^T P^T,
   * that can refactorize in part: after the entries of a few rows (and, by symmetry, the
   * same columns) of the matrix changed, refactorize() recomputes only the columns of L
   * that depend on them, the paths from those columns to the root of the elimination
   * tree, and keeps every other column as it is. Where a coefficient, a contact, a
   * damage or a plastic zone changes the matrix of a finite element problem on a few
   * cells from one step to the next, this costs a fraction of a factorization, and the
   * factor is still the exact one of the new matrix.
   *
   * The class has the interface of deal.II's SparseDirectUMFPACK: initialize() with a
   * matrix, then vmult() (and Tvmult(), the same for a symmetric matrix) multiplies with
   * its inverse, so that an object of this class serves wherever deal.II expects a
   * preconditioner or an inverse, for instance in SolverCG; solve() works in place. The
   * numeric work is done by cholesky::SparseCholesky (METIS nested dissection,
   * supernodal left-looking factorization with BLAS-3 kernels by default).
   *
   * @code
   *   SparseDirectCholesky solver;
   *   solver.initialize(system_matrix);      // ordering, analysis, factorization
   *   solver.vmult(solution, system_rhs);    // solution = A^{-1} system_rhs
   *
   *   // The coefficient changed on a few cells: assemble again (same sparsity pattern)
   *   // and list the rows of those cells' degrees of freedom.
   *   std::vector<types::global_dof_index> changed_rows;
   *   for (const auto &cell : changed_cells)
   *     {
   *       cell->get_dof_indices(local_dof_indices);
   *       changed_rows.insert(changed_rows.end(),
   *                           local_dof_indices.begin(), local_dof_indices.end());
   *     }
   *   solver.refactorize(system_matrix, changed_rows);
   *   solver.solve(system_rhs);              // in place: system_rhs is the solution now
   *
   *   // As the preconditioner of CG on a nearby matrix (the factor of a stale one):
   *   SolverControl            control(100, 1e-10 * system_rhs.l2_norm());
   *   SolverCG<Vector<double>> cg(control);
   *   cg.solve(other_matrix, solution, rhs, solver);
   * @endcode
   *
   * <h4>Updates and downdates</h4>
   *
   * A change that the caller knows as a sum of outer products, A + C C^T or A - C C^T with
   * C of a few columns (a penalty sqrt(k) e_i on a degree of freedom, a spring between
   * two), is applied to the factor in place by update() and downdate(), without a matrix:
   *
   * @code
   *   // A spring of stiffness k on the dof i: A + k e_i e_i^T.
   *   DynamicSparsityPattern dsp(system_matrix.m(), 1);
   *   dsp.add(i, 0);
   *   SparsityPattern pattern;
   *   pattern.copy_from(dsp);
   *   SparseMatrix<double> C(pattern);
   *   C.set(i, 0, std::sqrt(k));
   *   solver.update(C);                      // the factor of A + C C^T
   *   solver.downdate(C);                    // and back to A's
   * @endcode
   *
   * <h4>Matrices</h4>
   *
   * A dealii::SparseMatrix<double>, or a TrilinosWrappers::SparseMatrix held by one
   * process (a block-free matrix: for a block matrix, pass its monolithic form). Both
   * triangles are stored, as deal.II assembles them; the matrix must be symmetric to
   * 1e-10 relative and positive definite. Every entry of the sparsity pattern is kept,
   * explicit zeros included, so the pattern, and with it the analysis, stays the same
   * from one assembly to the next: refactorize() and factorize() require the pattern
   * that initialize() was given.
   *
   * A row whose values changed without being listed in refactorize() is found while the
   * values are copied in and recomputed as well: the list says where to look, it is not
   * trusted. The factor is therefore always the one of the matrix given last (with the
   * updates and downdates since), and equals what a fresh initialize() would compute to
   * rounding: the columns that are kept do not depend on what changed (column by column
   * they are equal bit for bit; supernodes may sum the updates of their descendants in
   * another order).
   *
   * <h4>Errors</h4>
   *
   * Errors are deal.II exceptions, thrown as AssertThrow throws them (in Release builds
   * too), each declared below. Their message (print_info(), the "Additional information"
   * of what()) is one line that says what is wrong and where: the column and value of a
   * pivot that is not positive, the two entries that break the symmetry, the changed row
   * out of range. After a failed initialize(), factorize() or refactorize() the object
   * holds no factorization until the next successful one.
   *
   * <h4>Threads</h4>
   *
   * vmult(), Tvmult() and solve() are const and may run concurrently with each other,
   * not with initialize(), factorize(), refactorize(), update() or downdate().
   *
   * @ingroup Solvers Preconditioners
   */
  class SparseDirectCholesky : public dealii::Subscriptor
  {
  public:
    /** Declare the type for container size. */
    using size_type = dealii::types::global_dof_index;

    /**
     * The choices made before the analysis; the defaults are the fast ones.
     */
    struct AdditionalData
    {
      /**
       * Constructor. See the members for the meaning of each argument.
       */
      AdditionalData(const cholesky::OrderingMethod      ordering  = cholesky::OrderingMethod::metis,
                     const cholesky::FactorizationMethod method    = cholesky::FactorizationMethod::supernodal,
                     const unsigned int                  n_threads = 1);

      /**
       * The fill-reducing ordering: METIS nested dissection (of the graph of mesh
       * vertices where the degrees of freedom come in threes, as in 3d elasticity), AMD,
       * or none.
       */
      cholesky::OrderingMethod ordering;

      /**
       * Supernodal (BLAS-3 kernels on dense blocks of columns) or column by column
       * (left-looking); both refactorize in part. The up-looking method refactorizes in
       * full.
       */
      cholesky::FactorizationMethod method;

      /**
       * Threads of the supernodal factorization and of the triangular solves (TBB tasks
       * over independent subtrees); 1 runs serially.
       */
      unsigned int n_threads;
    };

    /**
     * Constructor. The object holds no factorization until initialize() is called.
     */
    SparseDirectCholesky();

    /**
     * Compute the fill-reducing ordering, the symbolic analysis and the factorization of
     * @p matrix, forgetting any previous one.
     */
    void initialize(const dealii::SparseMatrix<double> &matrix,
                    const AdditionalData               &additional_data = AdditionalData());

    /**
     * Factorize every column of @p matrix again, which has the sparsity pattern given to
     * initialize(); the ordering and the analysis are kept.
     */
    void factorize(const dealii::SparseMatrix<double> &matrix);

    /**
     * Bring the factorization up to date with @p matrix, whose entries changed only in
     * the rows (and, the matrix being symmetric, the columns) @p changed_rows since the
     * last factorization: recompute the columns of L that depend on them and keep the
     * others. @p matrix has the sparsity pattern given to initialize(). The rows may be
     * listed in any order and more than once.
     *
     * Where the change is of low rank (a few rows, as a penalty on a few degrees of
     * freedom gives), updating the factor by it, as update() and downdate() do, costs less
     * than recomputing those columns: the solver weighs both and takes the cheaper
     * (cholesky::ChangeMethod::automatic; Statistics::method says which it took). Either
     * way the factor is the one of @p matrix.
     *
     * statistics() then says what it cost: Statistics::columns_recomputed,
     * Statistics::flops_recomputed (against Statistics::flops for a full
     * factorization) and Statistics::refactorize_seconds.
     */
    void refactorize(const dealii::SparseMatrix<double> &matrix, const std::vector<size_type> &changed_rows);

    /**
     * Update the factorization of A to that of A + C C^T in place, without recomputing
     * its columns (CHOLMOD's cholmod_updown): cheaper than refactorize() where the change
     * is a sum of a few outer products that the caller knows, such as a penalty
     * (a spring, a contact) sqrt(k) e_i on a few degrees of freedom, or an element's
     * matrix given as a few columns.
     *
     * @p C is n x k: a dealii::SparseMatrix on a rectangular SparsityPattern whose rows
     * are those of the factored matrix, one column per outer product. The rows of each
     * column must be coupled in the factor, as the degrees of freedom of one cell or one
     * vertex are (C C^T must fit the sparsity of L); a column whose rows are not is
     * refused, naming them. Stored entries of @p C that are zero are left out (they add
     * nothing to C C^T), so a pattern wider than the values is fine.
     *
     * The factor is then that of A + C C^T, and vmult() and solve() solve with it;
     * statistics() says what it cost (Statistics::flops_recomputed,
     * Statistics::columns_recomputed, Statistics::refactorize_seconds) and
     * Statistics::method is RefactorizationMethod::update. The solver keeps A + C C^T as
     * the matrix it factored, which a later refactorize() compares the matrix it is given
     * with: one that holds the change (assembled again) leaves the factor as it is but for
     * rounding, one with A as before takes the change back.
     *
     * Needs the supernodal method (AdditionalData::method) and a factorization
     * (ExcNotInitialized otherwise). Throws ExcInvalidModification for a @p C that cannot
     * be taken (another number of rows, a value that is not finite, rows the factor does
     * not couple) or another method; the factorization is then unchanged.
     */
    void update(const dealii::SparseMatrix<double> &C);

    /**
     * Downdate the factorization of A to that of A - C C^T in place, as update() (same
     * @p C, same errors). If A - C C^T is not positive definite, or so near to it that the
     * factor would keep only a few digits, throws ExcDowndateNotPositiveDefinite, naming
     * the column whose pivot would fail, and leaves the factorization that of A (the
     * columns the downdate changed recomputed from A, to rounding; put back bit for bit
     * after an update whose products fell outside A's pattern): vmult() and solve() still
     * solve with A.
     */
    void downdate(const dealii::SparseMatrix<double> &C);

#ifdef DEAL_II_WITH_TRILINOS
    /**
     * As initialize() above, for a Trilinos matrix held by one process (its communicator
     * has one process and it owns every row).
     */
    void initialize(const dealii::TrilinosWrappers::SparseMatrix &matrix,
                    const AdditionalData                         &additional_data = AdditionalData());

    /** As factorize() above, for a Trilinos matrix held by one process. */
    void factorize(const dealii::TrilinosWrappers::SparseMatrix &matrix);

    /** As refactorize() above, for a Trilinos matrix held by one process. */
    void refactorize(const dealii::TrilinosWrappers::SparseMatrix &matrix,
                     const std::vector<size_type>                 &changed_rows);
#endif

    /**
     * @name Functions that represent the inverse of a matrix
     * @{
     */

    /**
     * Preconditioner interface: dst = A^{-1} src. @p dst and @p src may be the same
     * vector.
     */
    void vmult(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const;

    /**
     * dst = A^{-T} src, which is vmult() since A is symmetric.
     */
    void Tvmult(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const;

    /**
     * Solve A x = b in place: @p rhs_and_solution holds b on entry and x on return.
     */
    void solve(dealii::Vector<double> &rhs_and_solution) const;

#ifdef DEAL_II_WITH_TRILINOS
    /** vmult() for a Trilinos vector held by one process. */
    void vmult(dealii::TrilinosWrappers::MPI::Vector &dst, const dealii::TrilinosWrappers::MPI::Vector &src) const;

    /** Tvmult() for a Trilinos vector held by one process. */
    void Tvmult(dealii::TrilinosWrappers::MPI::Vector &dst, const dealii::TrilinosWrappers::MPI::Vector &src) const;

    /** solve() for a Trilinos vector held by one process. */
    void solve(dealii::TrilinosWrappers::MPI::Vector &rhs_and_solution) const;
#endif

    /** @} */

    /** Number of rows of the factored matrix (0 before initialize()). */
    size_type m() const;

    /** Number of columns of the factored matrix (0 before initialize()). */
    size_type n() const;

    /**
     * What the last calls did and cost: sizes, fill, flops of a full factorization, and
     * of the last refactorize() the columns and flops it recomputed and its time.
     */
    const cholesky::SparseCholesky::Statistics &statistics() const;

    /**
     * @addtogroup Exceptions
     * @{
     */

    /**
     * vmult(), solve() or a refactorization without a factorization: before
     * initialize(), or after one that failed.
     */
    DeclExceptionMsg(ExcNotInitialized,
                     "SparseDirectCholesky holds no factorization: call initialize() first "
                     "(a failed initialize() or refactorization leaves none)");

    /**
     * A pivot that is not positive: the matrix is not positive definite. The column is
     * the matrix's own (the row of the degree of freedom), the pivot the value of
     * A(j,j) minus the updates of the columns before it.
     */
    DeclException2(ExcNotPositiveDefinite,
                   size_type,
                   double,
                   << "the matrix is not positive definite: the pivot of column " << arg1 << " is "
                   << arg2);

    /**
     * A matrix that cannot be factored, in the words of the solver: not square, not
     * symmetric (naming both entries), a value that is not finite (naming the entry),
     * another sparsity pattern than the one initialize() was given.
     */
    DeclException1(ExcInvalidMatrix, std::string, << arg1);

    /**
     * A downdate() that would leave a matrix that is not positive definite: the pivot of
     * the column (the matrix's own numbering) would be the value given. The factorization
     * stays that of the matrix before (downdate()).
     */
    DeclException2(ExcDowndateNotPositiveDefinite,
                   size_type,
                   double,
                   << "the downdate would leave the matrix not positive definite: the pivot of column " << arg1
                   << " would be " << arg2 << " (the factorization stays that of the matrix before)");

    /**
     * A C that update() or downdate() cannot take, in the words of the solver: another
     * number of rows than the matrix, a value that is not finite, a column whose rows the
     * factor does not couple (naming them); or a method other than the supernodal one.
     */
    DeclException1(ExcInvalidModification, std::string, << arg1);

    /** A changed row that the matrix does not have. */
    DeclException2(ExcRowOutOfRange,
                   size_type,
                   size_type,
                   << "changed row " << arg1 << " is out of range [0, " << arg2 << ")");

    /** A Trilinos matrix or vector shared by several processes. */
    DeclException1(ExcNotOneProcess,
                   unsigned int,
                   << "the Trilinos object is shared by " << arg1
                   << " processes: SparseDirectCholesky factors a matrix held by one process");

    /** @} */

  private:
    /** initialize(), factorize() and refactorize() for either kind of matrix. */
    template <typename Matrix>
    void initialize_from(const Matrix &matrix, const AdditionalData &additional_data);
    template <typename Matrix>
    void factorize_from(const Matrix &matrix);
    template <typename Matrix>
    void refactorize_from(const Matrix &matrix, const std::vector<size_type> &changed_rows);

    /** update() (@p sign +1) and downdate() (-1). */
    void modify(const dealii::SparseMatrix<double> &C, double sign);

    /** Copy the values of @p matrix into matrix_csc, which has its pattern. */
    void copy_values(const dealii::SparseMatrix<double> &matrix);
#ifdef DEAL_II_WITH_TRILINOS
    void copy_values(const dealii::TrilinosWrappers::SparseMatrix &matrix);
#endif

    /**
     * Run @p numeric_work (a call of the solver with matrix_csc) and turn the solver's
     * errors into the exceptions declared above.
     */
    template <typename Work>
    void factor_and_translate_errors(const Work &numeric_work);

    /** Throw ExcNotInitialized unless initialize() analyzed a matrix (its factorization may have failed since). */
    void assert_initialized() const;

    /** Throw ExcNotInitialized unless a factorization exists. */
    void assert_factored() const;

    /** Throw ExcRowOutOfRange for a row the matrix does not have; the rows as the solver takes them. */
    std::vector<Index> checked_rows(const std::vector<size_type> &changed_rows) const;

    /** x = A^{-1} b for vectors of n() entries in memory (which may be the same), checked by the callers. */
    void solve(const double *b, double *x) const;

    /** The solver, holding the ordering, the analysis and the factor. */
    cholesky::SparseCholesky cholesky_solver;

    /**
     * The last matrix in the solver's form (CSC, both triangles): its pattern is fixed by
     * initialize(), its values are copied in by every factorization.
     */
    sparse::CSCMatrix matrix_csc;

    /**
     * Where the entries of a deal.II matrix go in matrix_csc: found at the first matrix,
     * so that the values of the next ones are copied without a search.
     */
    sparse::DealiiCscMap dealii_map;

#ifdef DEAL_II_WITH_TRILINOS
    /** The same for a Trilinos matrix: the position of each entry in Epetra's order. */
    std::vector<Index> trilinos_positions;
#endif
  };
} // namespace warpchol
