#pragma once

#include <warpchol/backends/cholmod_reference.h>
#include <warpchol/backends/linear_solver.h>

#include <deal.II/lac/sparse_direct.h>

#include <memory>

/**
 * @file
 * The direct peers: what a user refactorizes with every step when the matrix changes.
 * Each keeps its symbolic analysis where its library allows it and factors in full.
 */
namespace warpchol::backends
{
  /**
   * CHOLMOD supernodal LL^T as a user calls it: its own choice of ordering (AMD, or METIS
   * when AMD fills much), analyzed once, the numeric factorization in full every step.
   */
  class CholmodSolver : public LinearSolver
  {
  public:
    CholmodSolver();
    std::string name() const override;
    /** The next factorize() analyzes anew (ordering and symbolic factorization). */
    void        topology_changed() override;
    void        factorize(const dealii::SparseMatrix<double> &matrix, const sparse::CSCMatrix &csc) override;
    void        solve(const std::vector<double> &b, std::vector<double> &x) override;
    std::size_t memory_bytes() const override;

  private:
    cholesky::CholmodReference cholmod;
    bool                       analyzed = false;
  };

  /**
   * deal.II's SparseDirectUMFPACK (LU, no use of symmetry), as step-8 and its successors
   * use it: every factorize() is UMFPACK's symbolic and numeric factorization.
   */
  class UmfpackSolver : public LinearSolver
  {
  public:
    std::string name() const override;
    void        factorize(const dealii::SparseMatrix<double> &matrix, const sparse::CSCMatrix &csc) override;
    void        solve(const std::vector<double> &b, std::vector<double> &x) override;
    /** Heap growth over the first factorization (UMFPACK does not report its size). */
    std::size_t memory_bytes() const override;

  private:
    dealii::SparseDirectUMFPACK umfpack;
    std::size_t                 factor_bytes = 0;
  };

  /** Eigen's factorization behind an EigenSolver (its type hidden in the source). */
  class EigenFactorization;

  /**
   * Eigen's sparse Cholesky as a user calls it: the pattern analyzed once, the numeric
   * factorization in full every step. Backend::eigen is SimplicialLLT with its AMD ordering
   * (column by column); Backend::eigen_cholmod is CholmodSupernodalLLT, Eigen's wrapper of
   * CHOLMOD's supernodal factorization.
   */
  class EigenSolver : public LinearSolver
  {
  public:
    /** @p backend: Backend::eigen or Backend::eigen_cholmod. */
    explicit EigenSolver(Backend backend);
    ~EigenSolver() override;
    std::string name() const override;
    void        factorize(const dealii::SparseMatrix<double> &matrix, const sparse::CSCMatrix &csc) override;
    void        solve(const std::vector<double> &b, std::vector<double> &x) override;
    /**
     * SimplicialLLT: L's entries and index arrays; the CHOLMOD wrapper hides its factor:
     * the heap's growth over the first factorization.
     */
    std::size_t memory_bytes() const override;

  private:
    Backend                             backend;
    std::unique_ptr<EigenFactorization> factorization;
    /** The heap's growth over the first factorization. */
    std::size_t                         heap_growth = 0;
  };
} // namespace warpchol::backends
