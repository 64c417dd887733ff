#pragma once

#include <warpchol/base/binary_io.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/small_dense.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/models/contribution_frames.h>

#include <array>
#include <atomic>
#include <exception>
#include <thread>
#include <vector>

/**
 * @file
 * A refresh of the factor on a thread of its own, beside the time steps: the idea of SOFA's
 * AsyncSparseLDLSolver and of Courtecuisse et al. (2014)'s asynchronous preconditioner.
 */
namespace warpchol::fem
{
  /**
   * Assembles and factors, on a thread of its own, the matrix of warp-canceling corotation
   * with every element re-rotated at the rotations of one step: the exact corotational matrix
   * in that step's nodal frames, R^T B R. While it runs, the steps go on with the factor
   * they have; when it is done, the model takes its matrix, its frames and its factor
   * (take()) at a step boundary, and starts it again on newer rotations.
   *
   * A refresh owns its copy of the system matrix and of the solver (the same analysis), so
   * that nothing it writes is read by the steps before take(). Its work is serial (one
   * thread): with two threads, one steps and one refreshes.
   *
   * What it computes depends only on the rotations it was given: a refresh started at step
   * k and taken at step k + lag gives the same bits whatever the timing, which is the
   * deterministic mode of Strategy = background (Model/Background lag > 0).
   */
  class BackgroundRefresh
  {
  public:
    /** A refresh of @p system's matrix and of @p solver's factor (analyzed). */
    BackgroundRefresh(const ElasticBody &body, const SystemCoefficients &coefficients,
                      const cholesky::SparseCholesky &solver);
    /** Waits for a refresh in flight. */
    ~BackgroundRefresh();

    BackgroundRefresh(const BackgroundRefresh &)            = delete;
    BackgroundRefresh &operator=(const BackgroundRefresh &) = delete;

    /**
     * Start refreshing for the rotations of step @p step (copied): @p element_rotations
     * Q_e and @p nodal_rotations S_v. Nothing may be in flight (running() false and the
     * last one taken).
     */
    void start(unsigned int step, const std::vector<Matrix3> &element_rotations,
               const std::vector<Matrix3> &nodal_rotations);

    /** Whether a refresh was started and not yet taken. */
    bool in_flight() const;
    /** Whether the refresh in flight is done (take() will not wait). */
    bool done() const;
    /** The step whose rotations the refresh in flight was started with. */
    unsigned int started_step() const;

    /**
     * Wait for the refresh in flight, then exchange its results with the model's: A's
     * values into @p system, the frames S_v^T Q_e of every element into @p frames (of
     * reference P = I), the factor into @p solver (all exchanged, not copied). Returns the
     * seconds it waited. Rethrows what the refresh threw (a matrix that is not positive
     * definite).
     */
    double take(SystemMatrix &system, ContributionFrames &frames, cholesky::SparseCholesky &solver);

    /** The seconds the last refresh taken worked (assembly and factorization). */
    double last_seconds() const;

    /**
     * Write the refresh in flight to a checkpoint: its step and rotations, from which
     * load() starts it again (it computes the same bits).
     */
    void save(BinaryWriter &writer) const;
    void load(BinaryReader &reader);

  private:
    /** The work of one refresh, on the worker thread. */
    void run();
    /** Wait for the worker thread, if any. */
    void join();

    const ElasticBody                  &body;
    SystemMatrix                        system;
    cholesky::SparseCholesky            solver;
    std::vector<std::array<Matrix3, 4>> frames;
    std::vector<Matrix3>                element_rotations;
    std::vector<Matrix3>                nodal_rotations;
    unsigned int                        step    = 0;
    bool                                started = false;
    std::atomic<bool>                   finished{false};
    std::exception_ptr                  failure;
    double                              work_seconds = 0;
    std::thread                         worker;
  };
} // namespace warpchol::fem
