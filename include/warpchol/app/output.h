#pragma once

#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/elasticity_model.h>
#include <warpchol/fem/small_dense.h>

#include <string>
#include <utility>
#include <vector>

/**
 * @file
 * What a run leaves on disk, in output/SCENE/: VTU files with a PVD time series, and the
 * per-step CSV log. Every file is written under a temporary name and renamed into place,
 * so that a reader (ParaView, a plotting script, an interrupted run) never meets a
 * half-written file, and what earlier steps wrote stays.
 */
namespace warpchol::app
{
  /** Create @p directory and its parents; throws InputError naming it on failure. */
  void create_directory(const std::string &directory);

  /**
   * VTU files SCENE-NNNNN.vtu with the displacement and velocity per vertex and, per cell,
   * whether the element was updated in the step, its error estimate (WCC) and the steps
   * since its last update; SCENE.pvd lists them with their times.
   */
  class VtuSeries
  {
  public:
    VtuSeries(const std::string &directory, const std::string &scene);

    /** Write the state after step @p step at time @p time and rewrite the PVD file. */
    void write(unsigned int step, double time, const fem::ElasticBody &body,
               const std::vector<fem::Vector3> &displacements,
               const std::vector<fem::Vector3> &velocities,
               const fem::ElementUpdateRecord  &record);

    std::size_t        n_files() const;
    const std::string &pvd_file() const;

  private:
    std::string                                 directory;
    std::string                                 scene;
    std::string                                 pvd_name;
    std::vector<std::pair<double, std::string>> times_and_names;
  };

  /** One row of the per-step log. */
  struct StepLogRow
  {
    unsigned int              step = 0;
    double                    time = 0;
    fem::StepStatistics       statistics;
    double                    n_elements     = 0;
    double                    step_seconds   = 0;
    double                    kinetic_energy = 0;
    double                    elastic_energy = 0;
  };

  /** The CSV log: a header row, then a row per step; the file is rewritten after each step. */
  class StepLog
  {
  public:
    explicit StepLog(const std::string &filename);

    void add(const StepLogRow &row);

    const std::string &filename() const;

    /** The header row (the column names). */
    static std::string header();

  private:
    std::string              file;
    std::vector<std::string> rows;
  };
} // namespace warpchol::app
