#include <warpchol/base/exceptions.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/models/background_refresh.h>

namespace warpchol::fem
{
  BackgroundRefresh::BackgroundRefresh(const ElasticBody &body, const SystemCoefficients &coefficients,
                                       const cholesky::SparseCholesky &analyzed)
    : body(body)
    , system(body, coefficients)
    , solver(analyzed)
  {
    // One thread each: the steps keep the others.
    system.set_thread_count(1);
    solver.set_thread_count(1);
    frames.resize(body.n_elements());
  }

  BackgroundRefresh::~BackgroundRefresh()
  {
    join();
  }

  void BackgroundRefresh::join()
  {
    if (worker.joinable())
      worker.join();
  }

  void BackgroundRefresh::start(const unsigned int started_at, const std::vector<Matrix3> &element_rotations,
                                const std::vector<Matrix3> &nodal_rotations)
  {
    if (started)
      throw Error("background refresh: start() while a refresh is in flight");
    join();
    this->element_rotations = element_rotations;
    this->nodal_rotations   = nodal_rotations;
    step                    = started_at;
    started                 = true;
    finished                = false;
    failure                 = nullptr;
    worker                  = std::thread([this] { run(); });
  }

  void BackgroundRefresh::run()
  {
    try
      {
        const Stopwatch stopwatch;
        // Every element re-rotated: T_a = S_a^T Q_e, as WarpCancelingModel stores them.
        for (unsigned int e = 0; e < body.n_elements(); ++e)
          for (unsigned int a = 0; a < 4; ++a)
            frames[e][a] = nodal_rotations[body.element_vertices(e)[a]].transpose() * element_rotations[e];
        system.assemble(ElementFrames::warped(frames));
        solver.factorize(system.lower());
        solver.prepare_preconditioner();
        work_seconds = stopwatch.seconds();
      }
    catch (...)
      {
        failure = std::current_exception();
      }
    finished = true;
  }

  bool BackgroundRefresh::in_flight() const
  {
    return started;
  }

  bool BackgroundRefresh::done() const
  {
    return started && finished;
  }

  unsigned int BackgroundRefresh::started_step() const
  {
    return step;
  }

  double BackgroundRefresh::take(SystemMatrix &model_system, ContributionFrames &model_frames,
                                 cholesky::SparseCholesky &model_solver)
  {
    if (!started)
      throw Error("background refresh: take() with no refresh in flight");
    const Stopwatch stopwatch;
    join();
    started = false;
    if (failure)
      std::rethrow_exception(failure);
    model_system.swap_values(system);
    model_frames.adopt(frames);
    // The solver's thread count stays with each: exchange everything else.
    const unsigned int model_threads = model_solver.settings().n_threads;
    std::swap(model_solver, solver);
    model_solver.set_thread_count(model_threads);
    solver.set_thread_count(1);
    return stopwatch.seconds();
  }

  double BackgroundRefresh::last_seconds() const
  {
    return work_seconds;
  }

  void BackgroundRefresh::save(BinaryWriter &writer) const
  {
    writer.section("background refresh");
    writer.write(started);
    if (!started)
      return;
    writer.write(step);
    writer.write(element_rotations);
    writer.write(nodal_rotations);
  }

  void BackgroundRefresh::load(BinaryReader &reader)
  {
    reader.expect_section("background refresh");
    join();
    started = false;
    if (!reader.get<bool>())
      return;
    const auto           started_at = reader.get<unsigned int>();
    std::vector<Matrix3> element, nodal;
    reader.read(element);
    reader.read(nodal);
    if (element.size() != body.n_elements() || nodal.size() != body.n_vertices())
      reader.fail("the background refresh in flight was started for another body");
    start(started_at, element, nodal);
  }
} // namespace warpchol::fem
