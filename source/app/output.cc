#include <warpchol/app/output.h>
#include <warpchol/base/atomic_file.h>
#include <warpchol/base/exceptions.h>

#include <deal.II/base/data_out_base.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>

#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace warpchol::app
{
  void create_directory(const std::string &directory)
  {
    std::error_code error;
    std::filesystem::create_directories(directory, error);
    if (error || !std::filesystem::is_directory(directory))
      throw InputError(directory + ": cannot create the output directory" +
                       (error ? ": " + error.message() : std::string()));
  }

  VtuSeries::VtuSeries(const std::string &directory, const std::string &scene)
    : directory(directory)
    , scene(scene)
    , pvd_name(directory + "/" + scene + ".pvd")
  {}

  VtuSeries::~VtuSeries()
  {
    if (pending.valid())
      pending.wait();
  }

  void VtuSeries::finish()
  {
    if (pending.valid())
      pending.get();
  }

  void VtuSeries::write(const unsigned int step, const double time, std::vector<BodySnapshot> bodies)
  {
    finish();
    pending = std::async(std::launch::async, [this, step, time, bodies = std::move(bodies)]() {
      write_now(step, time, bodies);
    });
  }

  namespace
  {
    /**
     * The fields of one body (@p index of @p n_bodies) as deal.II's patches. Every body
     * gets the same fields, so that their patches merge: the error estimate is 0 for a
     * body without one when another has it.
     */
    void build_body_patches(dealii::DataOut<3> &data_out, const BodySnapshot &snapshot,
                            const unsigned int index, const unsigned int n_bodies,
                            const bool with_error_estimate)
    {
      const fem::ElasticBody &body = *snapshot.body;
      // The dofs are numbered 3 v + c (ElasticBody): per-vertex 3-vectors are dof vectors.
      dealii::Vector<double> displacement(3 * body.n_vertices());
      dealii::Vector<double> velocity(3 * body.n_vertices());
      for (unsigned int v = 0; v < body.n_vertices(); ++v)
        for (unsigned int c = 0; c < 3; ++c)
          {
            displacement[3 * v + c] = snapshot.displacements[v][c];
            velocity[3 * v + c]     = snapshot.velocities[v][c];
          }
      const auto            &record  = snapshot.record;
      const unsigned int     n_cells = body.n_elements();
      dealii::Vector<double> updated(n_cells), steps_since_update(n_cells), error_estimate(n_cells),
        body_index(n_cells);
      for (unsigned int e = 0; e < n_cells; ++e)
        {
          updated[e]            = record.updated[e];
          steps_since_update[e] = record.steps_since_update[e];
          if (!record.error_estimate.empty())
            error_estimate[e] = record.error_estimate[e];
          body_index[e] = index;
        }

      using Interpretation = dealii::DataComponentInterpretation::DataComponentInterpretation;
      const std::vector<Interpretation> vector_field(
        3, dealii::DataComponentInterpretation::component_is_part_of_vector);
      data_out.attach_dof_handler(body.dof_handler());
      data_out.add_data_vector(displacement, std::vector<std::string>(3, "displacement"),
                               dealii::DataOut<3>::type_dof_data, vector_field);
      data_out.add_data_vector(velocity, std::vector<std::string>(3, "velocity"),
                               dealii::DataOut<3>::type_dof_data, vector_field);
      data_out.add_data_vector(updated, "updated", dealii::DataOut<3>::type_cell_data);
      data_out.add_data_vector(steps_since_update, "steps_since_update",
                               dealii::DataOut<3>::type_cell_data);
      if (with_error_estimate)
        data_out.add_data_vector(error_estimate, "error_estimate", dealii::DataOut<3>::type_cell_data);
      if (n_bodies > 1)
        data_out.add_data_vector(body_index, "body", dealii::DataOut<3>::type_cell_data);
      data_out.build_patches(body.mapping());
    }
  } // namespace

  void VtuSeries::write_now(const unsigned int step, const double time,
                            const std::vector<BodySnapshot> &bodies)
  {
    bool with_error_estimate = false;
    for (const auto &snapshot : bodies)
      with_error_estimate = with_error_estimate || !snapshot.record.error_estimate.empty();
    const unsigned int n_bodies = bodies.size();
    dealii::DataOut<3> data_out;
    build_body_patches(data_out, bodies[0], 0, n_bodies, with_error_estimate);
    for (unsigned int i = 1; i < n_bodies; ++i)
      {
        dealii::DataOut<3> other;
        build_body_patches(other, bodies[i], i, n_bodies, with_error_estimate);
        const fem::Vector3 shift = bodies[i].offset - bodies[0].offset;
        data_out.merge_patches(other, dealii::Point<3>(shift[0], shift[1], shift[2]));
      }
    // Fast compression: the files are a little larger, written in half the time.
    dealii::DataOutBase::VtkFlags flags;
    flags.compression_level = dealii::DataOutBase::VtkFlags::best_speed;
    data_out.set_flags(flags);

    std::ostringstream name;
    name << scene << "-" << std::setw(5) << std::setfill('0') << step << ".vtu";
    write_file_atomically(directory + "/" + name.str(),
                          [&](std::ostream &out) { data_out.write_vtu(out); });

    times_and_names.emplace_back(time, name.str());
    write_file_atomically(pvd_name, [&](std::ostream &out) {
      dealii::DataOutBase::write_pvd_record(out, times_and_names);
    });
  }

  void VtuSeries::save(BinaryWriter &writer) const
  {
    writer.section("VTU series");
    writer.write(static_cast<std::uint64_t>(times_and_names.size()));
    for (const auto &[time, name] : times_and_names)
      {
        writer.write(time);
        writer.write(name);
      }
  }

  void VtuSeries::load(BinaryReader &reader)
  {
    reader.expect_section("VTU series");
    const auto n = reader.get<std::uint64_t>();
    times_and_names.clear();
    for (std::uint64_t i = 0; i < n; ++i)
      {
        const auto  time = reader.get<double>();
        std::string name;
        reader.read(name);
        times_and_names.emplace_back(time, name);
      }
  }

  std::size_t VtuSeries::n_files() const
  {
    return times_and_names.size();
  }

  const std::string &VtuSeries::pvd_file() const
  {
    return pvd_name;
  }

  StepLog::StepLog(const std::string &filename, const bool with_error)
    : file(filename)
    , with_error(with_error)
  {}

  std::string StepLog::header() const
  {
    return std::string(
             "step,time,elements_updated,elements_updated_pct,refactorized,columns_recomputed_pct,"
             "flops_recomputed_pct,refresh,cg_iterations,t_rotations,t_error_estimate,t_assembly,"
             "t_factor,t_solve,t_iterations,t_step,kinetic_energy,elastic_energy,potential_energy,"
             "tool_energy,total_energy,external_work,tool_work_on_body,energy_ratio,update_threshold,"
             "velocity_error") +
           (with_error ? ",error_vs_corotational,rms_error_vs_corotational" : "");
  }

  void StepLog::add(const StepLogRow &row)
  {
    const auto &s       = row.statistics;
    const auto  percent = [](const double part, const double whole) {
      return whole > 0 ? 100 * part / whole : 0.0;
    };
    std::ostringstream line;
    line << std::setprecision(6) << row.step << "," << row.time << "," << s.elements_updated << ","
         << percent(s.elements_updated, row.n_elements) << "," << (s.refactorized ? 1 : 0) << ","
         << percent(s.columns_recomputed, s.n_columns) << ","
         << percent(s.flops_recomputed, s.flops_full) << "," << s.refresh << "," << s.cg_iterations
         << "," << s.t_rotations() << "," << s.t_error_estimate() << "," << s.t_assembly() << ","
         << s.t_factor() << "," << s.t_solve() << "," << s.t_iterations() << "," << row.step_seconds << "," << std::setprecision(10) << row.kinetic_energy << ","
         << row.elastic_energy << "," << row.potential_energy << "," << row.tool_energy << ","
         << row.total_energy << "," << row.external_work << "," << row.tool_work_on_body << ","
         << std::setprecision(6) << row.energy_ratio << ",";
    // Empty where the model has no threshold or did not measure its error.
    if (s.update_threshold >= 0)
      line << s.update_threshold;
    line << ",";
    if (s.velocity_error >= 0)
      line << s.velocity_error;
    if (with_error)
      line << "," << std::setprecision(6) << row.error_vs_corotational << ","
           << row.rms_error_vs_corotational;
    rows.push_back(line.str());
    // Rewriting the whole file costs more as the rows pile up (a third of a 100-step run
    // when done every step): every half second is enough for a reader to follow.
    if (rows.size() == 1 || since_written.seconds() > 0.5)
      flush();
  }

  void StepLog::flush()
  {
    if (written_rows == rows.size() && written_rows > 0)
      return;
    write_file_atomically(file, [&](std::ostream &out) {
      out << header() << "\n";
      for (const auto &text : rows)
        out << text << "\n";
    });
    written_rows = rows.size();
    since_written.restart();
  }

  StepLog::~StepLog()
  {
    // What was logged stays, also when a run ends by an error; a destructor must not throw.
    try
      {
        flush();
      }
    catch (...)
      {}
  }

  void StepLog::save(BinaryWriter &writer) const
  {
    writer.section("log");
    writer.write(rows);
  }

  void StepLog::load(BinaryReader &reader)
  {
    reader.expect_section("log");
    reader.read(rows);
    written_rows = 0;
  }

  const std::string &StepLog::filename() const
  {
    return file;
  }
} // namespace warpchol::app
