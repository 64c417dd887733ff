#include <warpchol/base/format.h>
#include <warpchol/backends/direct_solvers.h>
#include <warpchol/backends/linear_solver.h>
#include <warpchol/backends/trilinos_amg_cg.h>
#include <warpchol/base/exceptions.h>

#include <malloc.h>
#include <mpi.h>

// AddressSanitizer (the sanitizer build) replaces glibc's allocator: ask its own.
#if defined(__SANITIZE_ADDRESS__)
#  define WARPCHOL_ADDRESS_SANITIZER
#elif defined(__has_feature)
#  if __has_feature(address_sanitizer)
#    define WARPCHOL_ADDRESS_SANITIZER
#  endif
#endif
#ifdef WARPCHOL_ADDRESS_SANITIZER
#  include <sanitizer/allocator_interface.h>
#endif

#include <cstdlib>

namespace warpchol::backends
{
  std::vector<Backend> all_backends()
  {
    std::vector<Backend> backends;
    for (const auto &entry : backend_names)
      backends.push_back(entry.value);
    return backends;
  }

  std::string to_string(const Backend backend)
  {
    return name_of(backend_names, backend);
  }

  Backend parse_backend(const std::string &name)
  {
    return parse_name(backend_names, name, "backend");
  }

  bool replaces_factor(const Backend backend)
  {
    return backend != Backend::warpchol && backend != Backend::warp_preconditioned_cg;
  }

  bool iterates(const Backend backend)
  {
    return backend == Backend::trilinos_amg_cg || backend == Backend::warp_preconditioned_cg;
  }

  void LinearSolver::topology_changed()
  {}

  bool LinearSolver::is_iterative() const
  {
    return false;
  }

  unsigned int LinearSolver::last_iterations() const
  {
    return 0;
  }

  std::unique_ptr<LinearSolver> create_linear_solver(const Settings &settings,
                                                     const std::vector<std::vector<double>> &rigid_body_modes)
  {
    switch (settings.backend)
      {
        case Backend::cholmod:
          return std::make_unique<CholmodSolver>();
        case Backend::umfpack:
          return std::make_unique<UmfpackSolver>();
        case Backend::eigen:
        case Backend::eigen_cholmod:
          return std::make_unique<EigenSolver>(settings.backend);
        case Backend::trilinos_amg_cg:
          require_mpi();
          return std::make_unique<TrilinosAmgCgSolver>(settings, rigid_body_modes);
        default:
          break;
      }
    throw InputError("backend " + to_string(settings.backend) + " has no linear solver of its own: it uses warpchol's factor");
  }

  void require_mpi()
  {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (initialized)
      return;
    int provided = 0;
    if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS)
      throw Error("MPI could not be started (Solver/Backend = trilinos_amg_cg needs it)");
    std::atexit([] {
      int finalized = 0;
      MPI_Finalized(&finalized);
      if (!finalized)
        MPI_Finalize();
    });
  }

  std::size_t heap_bytes_in_use()
  {
#ifdef WARPCHOL_ADDRESS_SANITIZER
    // glibc's statistics stand still under AddressSanitizer, whose allocator serves
    // every malloc: every memory_bytes() would read 0.
    return __sanitizer_get_current_allocated_bytes();
#else
    // Small blocks (uordblks) and the large ones glibc maps on their own (hblkhd): a
    // factor's arrays are mostly the latter.
    const struct mallinfo2 info = mallinfo2();
    return info.uordblks + info.hblkhd;
#endif
  }

  std::size_t heap_growth_of(const std::function<void()> &action)
  {
    const std::size_t before = heap_bytes_in_use();
    action();
    const std::size_t after = heap_bytes_in_use();
    return after > before ? after - before : 0;
  }
} // namespace warpchol::backends
