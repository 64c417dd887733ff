#pragma once

#include <warpchol/base/binary_io.h>
#include <warpchol/base/types.h>
#include <warpchol/sparse/csc_matrix.h>

#include <vector>

/**
 * @file
 * The lower triangle of C = P^T A P that the factorizations read, kept in step with the
 * user's matrix A.
 */
namespace warpchol::cholesky
{
  /**
   * The permuted lower triangle C of a symmetric matrix A, and the map from A's stored
   * entries to C's. Built once from A's pattern (analyze); load() then copies new values
   * in O(nnz(A)), checking that A still has the analyzed pattern, holds no NaN or
   * infinity and (with full storage) is symmetric, and reports which columns of C
   * actually changed.
   */
  class PermutedMatrix
  {
  public:
    /**
     * Build the pattern of C from the pattern of @p matrix and the permutation
     * (perm[k] = column of A that becomes column k of C). Throws MatrixError if A is not
     * square or, with full storage, its pattern is not symmetric (naming an entry).
     */
    void setup(const sparse::CSCMatrix &matrix, const std::vector<Index> &permutation);

    /**
     * Copy the values of @p matrix into C. Its pattern is the one given to setup() or a
     * subset of it (the entries it leaves out are zeros: arithmetic drops explicit zeros).
     * Throws MatrixError, naming the entry, for an entry outside that pattern, a value that
     * is NaN or infinite, or (full storage) A(i,j) that differs from A(j,i) by more than
     * 1e-10 sqrt(|A(i,i) A(j,j)|); and for another size or storage. Returns the columns of
     * C (sorted) whose values differ from those of the previous load.
     */
    std::vector<Index> load(const sparse::CSCMatrix &matrix);

    /**
     * load(), with the values of @p matrix read from @p values (matrix.n_nonzeros() of them,
     * in the order of its entries) instead of matrix.values, which are not used.
     */
    std::vector<Index> load(const sparse::CSCMatrix &matrix, const double *values);

    /**
     * load() of the entries stored in @p columns of A (the user's numbering) only, for a
     * caller that knows no other stored entry changed, in value or in place, since the last
     * load: the cost is that of those columns and of A's column counts, not of nnz(A). The
     * first load reads everything.
     */
    std::vector<Index> load_columns(const sparse::CSCMatrix &matrix, const std::vector<Index> &columns);

    /** load_columns(), with the values of @p matrix read from @p values, as load() above reads them. */
    std::vector<Index> load_columns(const sparse::CSCMatrix &matrix, const double *values,
                                    const std::vector<Index> &columns);

    /**
     * Record that the factor now holds the loaded values: of every column, or of
     * @p columns of C only (the others were factored from what they hold already).
     */
    void mark_factored();
    void mark_factored(const std::vector<Index> &columns);

    /** An entry of C whose value changed: row and column of C, loaded minus factored value. */
    struct Change
    {
      Index  row;
      Index  column;
      double delta;
    };

    /** The entries of @p columns of C (sorted) whose loaded value differs from the factored one. */
    std::vector<Change> changes_since_factored(const std::vector<Index> &columns) const;

    /**
     * C += sum_t signs[t] c_t c_t^T, loaded and factored values alike (an update of the
     * factor by @p c, rows permuted and sorted), on the entries of C's pattern. Returns false
     * if some product falls outside it: C then no longer holds the factored matrix.
     */
    bool add_low_rank(const sparse::CSCMatrix &c, const std::vector<double> &signs);

    /** C, lower storage, permuted numbering. */
    const sparse::CSCMatrix &lower() const;

    /** Stored entries of the lower triangle of A (= nnz(C)). */
    Index n_nonzeros() const;

    /** Write the values of C (the last load) to a checkpoint. */
    void save(BinaryWriter &writer) const;
    /** Read what save() wrote; throws InputError if it does not fit the pattern of setup(). */
    void load(BinaryReader &reader);

  private:
    /**
     * The values of @p matrix (read from @p values) in the order of the entries of the
     * pattern given to setup(): @p values itself where @p matrix has that pattern (the
     * common case: a comparison of the arrays), else placed in subset_values, zeros where
     * a subset of the pattern leaves entries out. Throws MatrixError for another size or
     * storage and for an entry outside the pattern (naming it). With @p listed_columns
     * (load_columns()) the pattern is taken as the analyzed one if the column counts and the
     * rows of those columns are: the caller vouches that nothing else changed.
     */
    const double *values_in_analyzed_order(const sparse::CSCMatrix  &matrix,
                                           const double             *values,
                                           const std::vector<Index> *listed_columns = nullptr);

    /** load() of values in the analyzed pattern's order, once the pattern is checked. */
    std::vector<Index> load_values(const double *values);

    /**
     * A later load(): only the entries whose value differs from the last load's are
     * checked (finite, symmetric) and copied, all before any is written (a refused load
     * leaves C as it was). The comparison streams A's values in their order, the cost of
     * a memcmp; C's entries are gathered through the permutation only where they changed.
     */
    std::vector<Index> load_changed_values(const double *values);

    /**
     * Check and copy the entries @p changed of A (positions in A's storage, increasing) of
     * @p values, all checked before any is written; returns the columns of C that changed.
     * @p every_change_listed: every entry of @p values that differs from the last load is
     * in @p changed (load_changed_values()), so that C may be read through whole.
     */
    std::vector<Index> load_entries(const double *values, const std::vector<Index> &changed,
                                    bool every_change_listed = false);

    /**
     * C rewritten in its own order, each entry read from where it comes from in @p values
     * (checked already); returns the columns in which a value changed, increasing, or with
     * @p all_columns every column that holds an entry.
     */
    std::vector<Index> copy_in_order(const double *values, bool all_columns);

    /** Throw MatrixError for the value of A's stored entry @p p, NaN or infinite (naming it as such). */
    [[noreturn]] void refuse_value(Index p, double value) const;

    sparse::CSCMatrix  permuted_lower;
    std::vector<Index> permutation;
    std::vector<Index> inverse_permutation;
    /** source[k]: position in A's storage of the value of C's entry k. */
    std::vector<Index> source;
    /** mirror[k]: position of the symmetric twin of entry k in A (full storage), or -1. */
    std::vector<Index> mirror;
    /** The analyzed pattern of A, to reject a matrix with another one. */
    sparse::Storage    storage = sparse::Storage::lower;
    std::vector<Index> analyzed_column_start;
    std::vector<Index> analyzed_row_index;
    /** The values of a matrix whose pattern is a subset of the analyzed one, in the analyzed order. */
    std::vector<double> subset_values;
    /** A's values at the last load, in A's order; the entry of C each of A's entries is (source or mirror). */
    std::vector<double> input_values;
    std::vector<Index>  entry_of_input;
    /** Position of each column's diagonal entry in C, -1 if it has none. */
    std::vector<Index>  diagonal_entry;
    /** The values the factor was computed from (mark_factored()). */
    std::vector<double> factored_values;
    /** Column of C of each entry, for reporting changed columns. */
    std::vector<Index> entry_column;
    bool               loaded = false;
  };
} // namespace warpchol::cholesky
