#include <warpchol/backends/direct_solvers.h>
#include <warpchol/base/exceptions.h>

#include <deal.II/lac/vector.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>

namespace warpchol::backends
{
  namespace
  {
    /** Our CSC matrix (both triangles) in Eigen's form, the same pattern and values. */
    using EigenMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, Index>;

    void copy_to_eigen(const sparse::CSCMatrix &csc, EigenMatrix &matrix)
    {
      if (matrix.rows() != csc.n_rows)
        {
          // The pattern once; later calls copy the values only.
          matrix.resize(csc.n_rows, csc.n_cols);
          matrix.resizeNonZeros(csc.n_nonzeros());
          std::copy(csc.column_start.begin(), csc.column_start.end(), matrix.outerIndexPtr());
          std::copy(csc.row_index.begin(), csc.row_index.end(), matrix.innerIndexPtr());
        }
      std::copy(csc.values.begin(), csc.values.end(), matrix.valuePtr());
    }

    /** x = solver^-1 b for one of Eigen's sparse Cholesky solvers. */
    template <typename Solver>
    void eigen_solve(const Solver &solver, const std::vector<double> &b, std::vector<double> &x)
    {
      const Eigen::Map<const Eigen::VectorXd> rhs(b.data(), static_cast<Eigen::Index>(b.size()));
      x.resize(b.size());
      Eigen::Map<Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size())) = solver.solve(rhs);
    }

    /** Factor @p matrix with @p solver, its pattern analyzed on the first call. */
    template <typename Solver>
    void eigen_factorize(Solver &solver, const EigenMatrix &matrix, bool &analyzed, const std::string &name)
    {
      if (!analyzed)
        {
          solver.analyzePattern(matrix);
          analyzed = true;
        }
      solver.factorize(matrix);
      if (solver.info() != Eigen::Success)
        throw MatrixError(name + " failed: the system matrix is not positive definite");
    }
  } // namespace

  CholmodSolver::CholmodSolver()
    : cholmod(true)
  {}

  std::string CholmodSolver::name() const
  {
    return to_string(Backend::cholmod);
  }

  void CholmodSolver::factorize(const dealii::SparseMatrix<double> &, const sparse::CSCMatrix &csc)
  {
    if (!analyzed)
      {
        cholmod.analyze(csc);
        analyzed = true;
      }
    cholmod.factorize(csc);
  }

  void CholmodSolver::solve(const std::vector<double> &b, std::vector<double> &x)
  {
    x = cholmod.solve(b);
  }

  std::size_t CholmodSolver::memory_bytes() const
  {
    return cholmod.factor_bytes();
  }

  std::string UmfpackSolver::name() const
  {
    return to_string(Backend::umfpack);
  }

  void UmfpackSolver::factorize(const dealii::SparseMatrix<double> &matrix, const sparse::CSCMatrix &)
  {
    const bool        first  = factor_bytes == 0;
    const std::size_t before = first ? heap_bytes_in_use() : 0;
    try
      {
        umfpack.factorize(matrix);
      }
    catch (const dealii::ExceptionBase &error)
      {
        throw MatrixError("UMFPACK failed to factor the system matrix (singular?)");
      }
    if (first)
      factor_bytes = std::max<std::size_t>(heap_bytes_in_use() - std::min(before, heap_bytes_in_use()), 1);
  }

  void UmfpackSolver::solve(const std::vector<double> &b, std::vector<double> &x)
  {
    dealii::Vector<double> solution(b.begin(), b.end());
    umfpack.solve(solution);
    x.assign(solution.begin(), solution.end());
  }

  std::size_t UmfpackSolver::memory_bytes() const
  {
    return factor_bytes;
  }

  struct EigenSimplicialSolver::Implementation
  {
    EigenMatrix                                                                 matrix;
    Eigen::SimplicialLLT<EigenMatrix, Eigen::Lower, Eigen::AMDOrdering<Index>> solver;
    bool                                                                        analyzed = false;
  };

  EigenSimplicialSolver::EigenSimplicialSolver()
    : implementation(std::make_unique<Implementation>())
  {}

  EigenSimplicialSolver::~EigenSimplicialSolver() = default;

  std::string EigenSimplicialSolver::name() const
  {
    return to_string(Backend::eigen);
  }

  void EigenSimplicialSolver::factorize(const dealii::SparseMatrix<double> &, const sparse::CSCMatrix &csc)
  {
    copy_to_eigen(csc, implementation->matrix);
    eigen_factorize(implementation->solver, implementation->matrix, implementation->analyzed,
                    "Eigen's SimplicialLLT");
  }

  void EigenSimplicialSolver::solve(const std::vector<double> &b, std::vector<double> &x)
  {
    eigen_solve(implementation->solver, b, x);
  }

  std::size_t EigenSimplicialSolver::memory_bytes() const
  {
    // L's values and row indices, its column starts and the permutation.
    const auto &l = implementation->solver.matrixL();
    const Index n = implementation->matrix.rows();
    return static_cast<std::size_t>(l.nestedExpression().nonZeros()) * (sizeof(double) + sizeof(Index)) +
           static_cast<std::size_t>(3 * n + 1) * sizeof(Index);
  }

  struct EigenCholmodSolver::Implementation
  {
    EigenMatrix                                               matrix;
    Eigen::CholmodSupernodalLLT<EigenMatrix, Eigen::Lower>    solver;
    bool                                                      analyzed     = false;
    std::size_t                                               factor_bytes = 0;
  };

  EigenCholmodSolver::EigenCholmodSolver()
    : implementation(std::make_unique<Implementation>())
  {}

  EigenCholmodSolver::~EigenCholmodSolver() = default;

  std::string EigenCholmodSolver::name() const
  {
    return to_string(Backend::eigen_cholmod);
  }

  void EigenCholmodSolver::factorize(const dealii::SparseMatrix<double> &, const sparse::CSCMatrix &csc)
  {
    copy_to_eigen(csc, implementation->matrix);
    const bool        first  = !implementation->analyzed;
    const std::size_t before = heap_bytes_in_use();
    eigen_factorize(implementation->solver, implementation->matrix, implementation->analyzed,
                    "Eigen's CholmodSupernodalLLT");
    if (first)
      implementation->factor_bytes = heap_bytes_in_use() - std::min(before, heap_bytes_in_use());
  }

  void EigenCholmodSolver::solve(const std::vector<double> &b, std::vector<double> &x)
  {
    eigen_solve(implementation->solver, b, x);
  }

  std::size_t EigenCholmodSolver::memory_bytes() const
  {
    return implementation->factor_bytes;
  }
} // namespace warpchol::backends
