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

  } // namespace

  CholmodSolver::CholmodSolver()
    : cholmod(true)
  {}

  std::string CholmodSolver::name() const
  {
    return to_string(Backend::cholmod);
  }

  void CholmodSolver::topology_changed()
  {
    analyzed = false;
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
    try
      {
        if (factor_bytes > 0)
          umfpack.factorize(matrix);
        else
          factor_bytes = std::max<std::size_t>(heap_growth_of([&] { umfpack.factorize(matrix); }), 1);
      }
    catch (const dealii::ExceptionBase &)
      {
        throw MatrixError("UMFPACK failed to factor the system matrix (singular?)");
      }
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

  /** The matrix in Eigen's form and one of Eigen's solvers of it. */
  class EigenFactorization
  {
  public:
    virtual ~EigenFactorization() = default;
    /** Factor @p csc, analyzing its pattern on the first call. */
    virtual void factorize(const sparse::CSCMatrix &csc) = 0;
    virtual void solve(const std::vector<double> &b, std::vector<double> &x) const = 0;
    /** Bytes of the factor as Eigen stores it; 0 where Eigen does not tell (its CHOLMOD wrapper). */
    virtual std::size_t factor_bytes() const = 0;
  };

  namespace
  {
    using SimplicialLLT = Eigen::SimplicialLLT<EigenMatrix, Eigen::Lower, Eigen::AMDOrdering<Index>>;

    template <typename Solver>
    class EigenFactorizationOf : public EigenFactorization
    {
    public:
      explicit EigenFactorizationOf(std::string name)
        : name(std::move(name))
      {}

      void factorize(const sparse::CSCMatrix &csc) override
      {
        copy_to_eigen(csc, matrix);
        if (!analyzed)
          {
            solver.analyzePattern(matrix);
            analyzed = true;
          }
        solver.factorize(matrix);
        if (solver.info() != Eigen::Success)
          throw MatrixError(name + " failed: the system matrix is not positive definite");
      }

      void solve(const std::vector<double> &b, std::vector<double> &x) const override
      {
        const Eigen::Map<const Eigen::VectorXd> rhs(b.data(), static_cast<Eigen::Index>(b.size()));
        x.resize(b.size());
        Eigen::Map<Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size())) = solver.solve(rhs);
      }

      std::size_t factor_bytes() const override
      {
        // L's values and row indices, its column starts and the permutation.
        if constexpr (std::is_same_v<Solver, SimplicialLLT>)
          return static_cast<std::size_t>(solver.matrixL().nestedExpression().nonZeros()) *
                   (sizeof(double) + sizeof(Index)) +
                 static_cast<std::size_t>(3 * matrix.rows() + 1) * sizeof(Index);
        return 0;
      }

    private:
      std::string name;
      EigenMatrix matrix;
      Solver      solver;
      bool        analyzed = false;
    };
  } // namespace

  EigenSolver::EigenSolver(const Backend backend)
    : backend(backend)
  {
    if (backend == Backend::eigen)
      factorization = std::make_unique<EigenFactorizationOf<SimplicialLLT>>("Eigen's SimplicialLLT");
    else if (backend == Backend::eigen_cholmod)
      factorization = std::make_unique<EigenFactorizationOf<Eigen::CholmodSupernodalLLT<EigenMatrix, Eigen::Lower>>>(
        "Eigen's CholmodSupernodalLLT");
    else
      throw InputError("EigenSolver: " + to_string(backend) + " is not one of Eigen's");
  }

  EigenSolver::~EigenSolver() = default;

  std::string EigenSolver::name() const
  {
    return to_string(backend);
  }

  void EigenSolver::factorize(const dealii::SparseMatrix<double> &, const sparse::CSCMatrix &csc)
  {
    if (heap_growth > 0)
      factorization->factorize(csc);
    else
      heap_growth = std::max<std::size_t>(heap_growth_of([&] { factorization->factorize(csc); }), 1);
  }

  void EigenSolver::solve(const std::vector<double> &b, std::vector<double> &x)
  {
    factorization->solve(b, x);
  }

  std::size_t EigenSolver::memory_bytes() const
  {
    const std::size_t counted = factorization->factor_bytes();
    return counted > 0 ? counted : heap_growth;
  }
} // namespace warpchol::backends
