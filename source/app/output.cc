#include <warpchol/app/output.h>
#include <warpchol/base/atomic_file.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/cholesky/statistics_fields.h>

#include <deal.II/base/data_out_base.h>
#include <deal.II/lac/vector.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/numerics/data_out.h>

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <sched.h>
#include <filesystem>
#include <functional>
#include <unistd.h>
#include <iomanip>
#include <sstream>
#include <thread>
#include <type_traits>
#include <variant>

namespace warpchol::app
{
  void create_directory(const std::string &directory)
  {
    // The system's reason as part of a sentence: "not a directory".
    const auto reason = [](const int error_number) {
      std::string text = std::strerror(error_number);
      text[0]          = static_cast<char>(std::tolower(static_cast<unsigned char>(text[0])));
      return text;
    };
    std::error_code error;
    std::filesystem::create_directories(directory, error);
    if (error || !std::filesystem::is_directory(directory))
      throw OutputError(directory + ": cannot create the output directory: " +
                        (error ? reason(error.value()) : std::string("a file of that name is in the way")));
    // Creating a file is the only sure test: permissions, a read-only file system, root.
    const std::string probe = directory + "/.warpchol-write-test." + std::to_string(::getpid());
    const int         descriptor = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (descriptor < 0)
      {
        const int error_number = errno;
        throw OutputError(directory + ": cannot write in the output directory: " + reason(error_number));
      }
    ::close(descriptor);
    std::remove(probe.c_str());
    // A run killed while it wrote a file left its temporary: the next one clears it away.
    remove_stale_temporaries(directory);
  }

  namespace
  {
    /** The cores this process may run on (its affinity mask), at least 1. */
    unsigned int allowed_cores()
    {
      cpu_set_t set;
      CPU_ZERO(&set);
      if (sched_getaffinity(0, sizeof set, &set) != 0)
        return std::max(1u, std::thread::hardware_concurrency());
      return std::max(1, CPU_COUNT(&set));
    }
  } // namespace

  VtuSeries::VtuSeries(const std::string &directory, const std::string &scene,
                       const std::string &precision)
    : directory(directory)
    , scene(scene)
    , precision(precision)
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

  bool VtuSeries::writes_in_background()
  {
    return allowed_cores() >= 2;
  }

  void VtuSeries::write(const unsigned int step, const double time, std::vector<BodySnapshot> bodies)
  {
    finish();
    if (!writes_in_background())
      {
        write_now(step, time, bodies);
        return;
      }
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
      dealii::Vector<double> rerotated(n_cells), steps_since_rerotation(n_cells), error_estimate(n_cells),
        body_index(n_cells);
      for (unsigned int e = 0; e < n_cells; ++e)
        {
          rerotated[e]              = record.rerotated[e];
          steps_since_rerotation[e] = record.steps_since_rerotation[e];
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
      data_out.add_data_vector(rerotated, "rerotated", dealii::DataOut<3>::type_cell_data);
      data_out.add_data_vector(steps_since_rerotation, "steps_since_rerotation",
                               dealii::DataOut<3>::type_cell_data);
      if (with_error_estimate)
        data_out.add_data_vector(error_estimate, "error_estimate", dealii::DataOut<3>::type_cell_data);
      if (n_bodies > 1)
        data_out.add_data_vector(body_index, "body", dealii::DataOut<3>::type_cell_data);
      // Cuts and grasps. DataOut keeps references: the vectors, and the scalar dofs that
      // number "grasped" vertex by vertex, must live until build_patches().
      dealii::Vector<double>      removed, cut_step, grasped, contact_force, contact_gap;
      dealii::FE_SimplexP<3>      scalar_element(1);
      dealii::DoFHandler<3>       scalar_dofs(body.triangulation());
      if (!snapshot.cut_steps.empty() || !snapshot.contact_gaps.empty())
        scalar_dofs.distribute_dofs(scalar_element);
      if (!snapshot.contact_forces.empty())
        {
          contact_force.reinit(3 * body.n_vertices());
          for (unsigned int v = 0; v < body.n_vertices(); ++v)
            for (unsigned int c = 0; c < 3; ++c)
              contact_force[3 * v + c] = snapshot.contact_forces[v][c];
          data_out.add_data_vector(contact_force, std::vector<std::string>(3, "contact_force"),
                                   dealii::DataOut<3>::type_dof_data, vector_field);
          contact_gap.reinit(scalar_dofs.n_dofs());
          for (const auto &cell : scalar_dofs.active_cell_iterators())
            for (unsigned int a = 0; a < 4; ++a)
              contact_gap[cell->vertex_dof_index(a, 0)] = snapshot.contact_gaps[cell->vertex_index(a)];
          data_out.add_data_vector(scalar_dofs, contact_gap, "contact_gap");
        }
      if (!snapshot.cut_steps.empty())
        {
          removed.reinit(n_cells);
          cut_step.reinit(n_cells);
          for (unsigned int e = 0; e < n_cells; ++e)
            {
              cut_step[e] = snapshot.cut_steps[e];
              removed[e]  = snapshot.cut_steps[e] >= 0 ? 1 : 0;
            }
          data_out.add_data_vector(removed, "removed", dealii::DataOut<3>::type_cell_data);
          data_out.add_data_vector(cut_step, "cut_step", dealii::DataOut<3>::type_cell_data);
          grasped.reinit(scalar_dofs.n_dofs());
          for (const auto &cell : scalar_dofs.active_cell_iterators())
            for (unsigned int a = 0; a < 4; ++a)
              grasped[cell->vertex_dof_index(a, 0)] = snapshot.grasped[cell->vertex_index(a)];
          data_out.add_data_vector(scalar_dofs, grasped, "grasped");
        }
      data_out.build_patches(body.mapping());
    }
  } // namespace

  namespace
  {
    /** Base64 of @p size bytes at @p bytes (RFC 4648, padded), VTK's binary encoding. */
    std::string base64(const unsigned char *bytes, const std::size_t size)
    {
      static const char alphabet[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
      std::string text;
      text.reserve(4 * ((size + 2) / 3));
      for (std::size_t i = 0; i < size; i += 3)
        {
          const unsigned int n = std::min<std::size_t>(3, size - i);
          const std::uint32_t group = (bytes[i] << 16) | (n > 1 ? bytes[i + 1] << 8 : 0) |
                                      (n > 2 ? bytes[i + 2] : 0);
          text += alphabet[(group >> 18) & 63];
          text += alphabet[(group >> 12) & 63];
          text += n > 1 ? alphabet[(group >> 6) & 63] : '=';
          text += n > 2 ? alphabet[group & 63] : '=';
        }
      return text;
    }

    /**
     * A DataArray in VTK's compressed binary form (header_type UInt64, one zlib block):
     * the header (1 block, its size, the size of the last block, its compressed size)
     * and the compressed block, each in base64.
     */
    template <typename Number>
    void write_data_array(std::ostream &out, const std::string &attributes,
                          const std::vector<Number> &values)
    {
      const auto  *bytes = reinterpret_cast<const Bytef *>(values.data());
      const uLong  size  = values.size() * sizeof(Number);
      uLongf       compressed_size = compressBound(size);
      std::vector<Bytef> compressed(compressed_size);
      if (compress2(compressed.data(), &compressed_size, bytes, size, Z_BEST_SPEED) != Z_OK)
        throw Error("zlib failed to compress a VTU array");
      const std::uint64_t header[4] = {1, size, size, compressed_size};
      out << "<DataArray " << attributes << " format=\"binary\">\n"
          << base64(reinterpret_cast<const unsigned char *>(header), sizeof(header))
          << base64(compressed.data(), compressed_size) << "\n</DataArray>\n";
    }

    /**
     * The VTU file of @p bodies in double precision, which deal.II 9.4's DataOut cannot
     * write (it writes Float32): the mesh's vertices once each (rest positions, each body
     * shifted by its offset from the first one's), the tetrahedra, and the fields of
     * build_body_patches() with the same names: per vertex displacement and velocity, per
     * cell rerotated, steps_since_rerotation, error_estimate and body.
     */
    void write_vtu_float64(std::ostream &out, const std::vector<BodySnapshot> &bodies,
                           const bool with_error_estimate)
    {
      std::vector<double>        points, displacements, velocities;
      std::vector<double>        rerotated, steps_since_rerotation, error_estimate, body_index, removed, cut_step, grasped;
      std::vector<double>        contact_forces, contact_gaps;
      const bool                 with_surgery = !bodies[0].cut_steps.empty();
      const bool                 with_contact = !bodies[0].contact_forces.empty();
      std::vector<std::int64_t>  connectivity, offsets;
      std::vector<std::uint8_t>  types;
      for (unsigned int i = 0; i < bodies.size(); ++i)
        {
          const BodySnapshot     &snapshot = bodies[i];
          const fem::ElasticBody &body     = *snapshot.body;
          const fem::Vector3      shift    = snapshot.offset - bodies[0].offset;
          const std::int64_t      first    = points.size() / 3;
          for (unsigned int v = 0; v < body.n_vertices(); ++v)
            for (unsigned int c = 0; c < 3; ++c)
              {
                points.push_back(body.rest_positions()[v][c] + shift[c]);
                displacements.push_back(snapshot.displacements[v][c]);
                velocities.push_back(snapshot.velocities[v][c]);
              }
          if (with_surgery)
            for (unsigned int v = 0; v < body.n_vertices(); ++v)
              grasped.push_back(snapshot.grasped[v]);
          if (with_contact)
            for (unsigned int v = 0; v < body.n_vertices(); ++v)
              {
                for (unsigned int c = 0; c < 3; ++c)
                  contact_forces.push_back(snapshot.contact_forces[v][c]);
                contact_gaps.push_back(snapshot.contact_gaps[v]);
              }
          const auto &record = snapshot.record;
          for (unsigned int e = 0; e < body.n_elements(); ++e)
            {
              for (const unsigned int v : body.element_vertices(e))
                connectivity.push_back(first + v);
              offsets.push_back(connectivity.size());
              types.push_back(10); // VTK_TETRA
              rerotated.push_back(record.rerotated[e]);
              steps_since_rerotation.push_back(record.steps_since_rerotation[e]);
              error_estimate.push_back(record.error_estimate.empty() ? 0.0 : record.error_estimate[e]);
              body_index.push_back(i);
              if (with_surgery)
                {
                  cut_step.push_back(snapshot.cut_steps[e]);
                  removed.push_back(snapshot.cut_steps[e] >= 0 ? 1 : 0);
                }
            }
        }
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
      const char *byte_order = "BigEndian";
#else
      const char *byte_order = "LittleEndian";
#endif
      out << "<?xml version=\"1.0\"?>\n"
          << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"" << byte_order
          << "\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n"
          << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << points.size() / 3
          << "\" NumberOfCells=\"" << types.size() << "\">\n<Points>\n";
      write_data_array(out, "type=\"Float64\" NumberOfComponents=\"3\"", points);
      out << "</Points>\n<Cells>\n";
      write_data_array(out, "type=\"Int64\" Name=\"connectivity\"", connectivity);
      write_data_array(out, "type=\"Int64\" Name=\"offsets\"", offsets);
      write_data_array(out, "type=\"UInt8\" Name=\"types\"", types);
      out << "</Cells>\n<PointData Vectors=\"displacement\">\n";
      write_data_array(out, "type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\"", displacements);
      write_data_array(out, "type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\"", velocities);
      if (with_surgery)
        write_data_array(out, "type=\"Float64\" Name=\"grasped\"", grasped);
      if (with_contact)
        {
          write_data_array(out, "type=\"Float64\" Name=\"contact_force\" NumberOfComponents=\"3\"", contact_forces);
          write_data_array(out, "type=\"Float64\" Name=\"contact_gap\"", contact_gaps);
        }
      out << "</PointData>\n<CellData>\n";
      write_data_array(out, "type=\"Float64\" Name=\"rerotated\"", rerotated);
      write_data_array(out, "type=\"Float64\" Name=\"steps_since_rerotation\"", steps_since_rerotation);
      if (with_error_estimate)
        write_data_array(out, "type=\"Float64\" Name=\"error_estimate\"", error_estimate);
      if (bodies.size() > 1)
        write_data_array(out, "type=\"Float64\" Name=\"body\"", body_index);
      if (with_surgery)
        {
          write_data_array(out, "type=\"Float64\" Name=\"removed\"", removed);
          write_data_array(out, "type=\"Float64\" Name=\"cut_step\"", cut_step);
        }
      out << "</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
    }

    /** The obstacles' triangles as a VTU file (Float64), with the cell field "obstacle" (1, 2, ...). */
    void write_obstacles_vtu(std::ostream &out, const std::vector<fem::TriangleSurface> &obstacles)
    {
      std::vector<double>       points, obstacle_index;
      std::vector<std::int64_t> connectivity, offsets;
      std::vector<std::uint8_t> types;
      for (std::size_t o = 0; o < obstacles.size(); ++o)
        {
          const std::int64_t first = points.size() / 3;
          for (const fem::Vector3 &point : obstacles[o].points)
            points.insert(points.end(), {point[0], point[1], point[2]});
          for (const auto &triangle : obstacles[o].triangles)
            {
              for (const unsigned int corner : triangle)
                connectivity.push_back(first + corner);
              offsets.push_back(connectivity.size());
              types.push_back(5); // VTK_TRIANGLE
              obstacle_index.push_back(o + 1);
            }
        }
      out << "<?xml version=\"1.0\"?>\n"
          << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" header_type=\"UInt64\" "
             "compressor=\"vtkZLibDataCompressor\">\n"
          << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << points.size() / 3 << "\" NumberOfCells=\""
          << types.size() << "\">\n<Points>\n";
      write_data_array(out, "type=\"Float64\" NumberOfComponents=\"3\"", points);
      out << "</Points>\n<Cells>\n";
      write_data_array(out, "type=\"Int64\" Name=\"connectivity\"", connectivity);
      write_data_array(out, "type=\"Int64\" Name=\"offsets\"", offsets);
      write_data_array(out, "type=\"UInt8\" Name=\"types\"", types);
      out << "</Cells>\n<CellData>\n";
      write_data_array(out, "type=\"Float64\" Name=\"obstacle\"", obstacle_index);
      out << "</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
    }
  } // namespace

  void VtuSeries::write_now(const unsigned int step, const double time,
                            const std::vector<BodySnapshot> &bodies)
  {
    bool with_error_estimate = false;
    for (const auto &snapshot : bodies)
      with_error_estimate = with_error_estimate || !snapshot.record.error_estimate.empty();
    std::ostringstream name;
    name << scene << "-" << std::setw(5) << std::setfill('0') << step << ".vtu";
    if (precision == "float64")
      write_file_atomically(directory + "/" + name.str(), [&](std::ostream &out) {
        write_vtu_float64(out, bodies, with_error_estimate);
      });
    else
      write_deal_ii_vtu(directory + "/" + name.str(), bodies, with_error_estimate);

    times_and_names.emplace_back(time, name.str());
    if (!bodies[0].obstacles.empty())
      {
        std::ostringstream obstacle_name;
        obstacle_name << scene << "-obstacles-" << std::setw(5) << std::setfill('0') << step << ".vtu";
        write_file_atomically(directory + "/" + obstacle_name.str(),
                              [&](std::ostream &out) { write_obstacles_vtu(out, bodies[0].obstacles); });
        obstacle_times_and_names.emplace_back(time, obstacle_name.str());
      }
    write_file_atomically(pvd_name, [&](std::ostream &out) {
      if (obstacle_times_and_names.empty())
        {
          dealii::DataOutBase::write_pvd_record(out, times_and_names);
          return;
        }
      // The body as part 0 and the obstacles as part 1 of each time: ParaView shows both.
      out << std::setprecision(16) << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
      for (const auto &[when, file] : times_and_names)
        out << "  <DataSet timestep=\"" << when << "\" group=\"\" part=\"0\" file=\"" << file << "\"/>\n";
      for (const auto &[when, file] : obstacle_times_and_names)
        out << "  <DataSet timestep=\"" << when << "\" group=\"\" part=\"1\" file=\"" << file << "\"/>\n";
      out << "</Collection>\n</VTKFile>\n";
    });
  }

  void VtuSeries::write_deal_ii_vtu(const std::string &filename, const std::vector<BodySnapshot> &bodies,
                                    const bool with_error_estimate) const
  {
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
    // Without the writing time in its header, a step's file is the same bytes on every run.
    flags.print_date_and_time = false;
    data_out.set_flags(flags);
    write_file_atomically(filename, [&](std::ostream &out) { data_out.write_vtu(out); });
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

  StepLog::StepLog(const std::string &filename, const bool with_error, const bool with_contact)
    : file(filename)
    , with_error(with_error)
    , with_contact(with_contact)
  {}

  namespace
  {
    /** A column of the log: its name and how a row writes its value. */
    struct LogColumn
    {
      const char                                                  *name;
      std::function<void(std::ostream &, const StepLogRow &row)> write;
    };

    double percent(const double part, const double whole)
    {
      return whole > 0 ? 100 * part / whole : 0.0;
    }

    /** A column of @p value to 6 digits (10 for the energies). */
    LogColumn column(const char *name, double (*value)(const StepLogRow &), const int digits = 6)
    {
      return {name, [value, digits](std::ostream &out, const StepLogRow &row) {
                out << std::setprecision(digits) << value(row);
              }};
    }

    /** A column of a count, written as an integer. */
    LogColumn count(const char *name, long long (*value)(const StepLogRow &))
    {
      return {name, [value](std::ostream &out, const StepLogRow &row) { out << value(row); }};
    }

    /** A column of @p value, empty where it is negative (not measured, not the model's). */
    LogColumn measured(const char *name, double (*value)(const StepLogRow &))
    {
      return {name, [value](std::ostream &out, const StepLogRow &row) {
                if (value(row) >= 0)
                  out << std::setprecision(6) << value(row);
              }};
    }

    /**
     * The column of a solver statistic (cholesky::statistics_fields()): the value after the
     * step's last factorization, empty in a step that factored nothing or where the
     * statistic is not set (what was weighed, when no update was).
     */
    LogColumn solver_column(const cholesky::StatisticsField &field)
    {
      return {field.log_column, [&field](std::ostream &out, const StepLogRow &row) {
                const cholesky::SparseCholesky::Statistics &factorization = row.statistics.factorization;
                if (!row.statistics.refactorized || !field.is_set(factorization))
                  return;
                std::visit(
                  [&out](const auto &value) {
                    if constexpr (std::is_same_v<std::decay_t<decltype(value)>, double>)
                      out << std::setprecision(6) << value;
                    else
                      out << value;
                  },
                  field.value(factorization));
              }};
    }

    /**
     * The columns of the step itself, before the solver's: one entry per column in the
     * log's order, a table that reads as the header does (hence its length).
     */
    std::vector<LogColumn> step_columns()
    {
      using Row = StepLogRow;
      return {
        count("step", [](const Row &r) -> long long { return r.step; }),
        column("time", [](const Row &r) { return r.time; }),
        count("elements_rerotated", [](const Row &r) -> long long { return r.statistics.elements_rerotated; }),
        column("elements_rerotated_pct", [](const Row &r) { return percent(r.statistics.elements_rerotated, r.n_elements); }),
        count("refactorized", [](const Row &r) -> long long { return r.statistics.refactorized ? 1 : 0; }),
        column("columns_recomputed_pct",
               [](const Row &r) { return percent(r.statistics.columns_recomputed, r.statistics.n_columns); }),
        column("flops_recomputed_pct",
               [](const Row &r) { return percent(r.statistics.flops_recomputed, r.statistics.flops_full); }),
        {"refresh", [](std::ostream &out, const Row &r) { out << r.statistics.refresh; }},
        count("cg_iterations", [](const Row &r) -> long long { return r.statistics.cg_iterations; }),
        column("t_rotations", [](const Row &r) { return r.statistics.t_rotations(); }),
        column("t_error_estimate", [](const Row &r) { return r.statistics.t_error_estimate(); }),
        column("t_assembly", [](const Row &r) { return r.statistics.t_assembly(); }),
        column("t_factor", [](const Row &r) { return r.statistics.t_factor(); }),
        column("t_solve", [](const Row &r) { return r.statistics.t_solve(); }),
        column("t_iterations", [](const Row &r) { return r.statistics.t_iterations(); }),
        column("t_step", [](const Row &r) { return r.step_seconds; }),
        column("kinetic_energy", [](const Row &r) { return r.kinetic_energy; }, 10),
        column("elastic_energy", [](const Row &r) { return r.elastic_energy; }, 10),
        column("potential_energy", [](const Row &r) { return r.potential_energy; }, 10),
        column("tool_energy", [](const Row &r) { return r.tool_energy; }, 10),
        column("total_energy", [](const Row &r) { return r.total_energy; }, 10),
        column("external_work", [](const Row &r) { return r.external_work; }, 10),
        column("tool_work_on_body", [](const Row &r) { return r.tool_work_on_body; }, 10),
        column("change_energy", [](const Row &r) { return r.change_energy; }, 10),
        column("energy_ratio", [](const Row &r) { return r.energy_ratio; }),
        measured("rerotation_threshold", [](const Row &r) { return r.statistics.rerotation_threshold; }),
        measured("velocity_error", [](const Row &r) { return r.statistics.velocity_error; }),
        // The automatic strategy's choice, what it predicted and what the step then spent
        // keeping its factor and solving; the age of a background refresh's factor.
        {"choice", [](std::ostream &out, const Row &r) { out << fem::to_string(r.statistics.choice); }},
        measured("t_predicted", [](const Row &r) { return r.statistics.predicted_seconds; }),
        column("t_strategy", [](const Row &r) { return r.statistics.strategy_seconds(); }),
        {"factor_lag",
         [](std::ostream &out, const Row &r) {
           if (r.statistics.factor_lag >= 0)
             out << r.statistics.factor_lag;
         }},
        // A cut, grasp or material change: what it did and what its columns cost.
        count("elements_cut", [](const Row &r) -> long long { return r.statistics.elements_cut; }),
        count("vertices_grasped", [](const Row &r) -> long long { return r.statistics.vertices_grasped; }),
        count("vertices_released", [](const Row &r) -> long long { return r.statistics.vertices_released; }),
        count("elements_changed", [](const Row &r) -> long long { return r.statistics.elements_changed; }),
        column("change_columns_pct",
               [](const Row &r) { return percent(r.statistics.change_columns, r.statistics.n_columns); }),
        column("change_flops_pct", [](const Row &r) { return percent(r.statistics.change_flops, r.statistics.flops_full); }),
        column("t_change", [](const Row &r) { return r.statistics.stages.seconds(fem::stage::change); })};
    }

    /**
     * The log's columns, each listed once: the header names them, a row writes them in this
     * order. The solver's (how the step's factorization took its changes, and what it
     * weighed) are those of cholesky::statistics_fields() with a log column; the trajectory
     * error's two columns come last, with a reference run only.
     */
    const std::vector<LogColumn> &log_columns()
    {
      static const std::vector<LogColumn> columns = [] {
        std::vector<LogColumn> all = step_columns();
        for (const cholesky::StatisticsField &field : cholesky::statistics_fields())
          if (field.log_column != nullptr)
            all.push_back(solver_column(field));
        all.push_back(column("error_vs_corotational", [](const StepLogRow &r) { return r.error_vs_corotational; }));
        all.push_back(
          column("rms_error_vs_corotational", [](const StepLogRow &r) { return r.rms_error_vs_corotational; }));
        return all;
      }();
      return columns;
    }

    /** The trajectory error's columns, written with a reference run only: the table's last ones. */
    constexpr std::size_t n_error_columns = 2;
  } // namespace

  std::string StepLog::header() const
  {
    const auto &columns = log_columns();
    std::string names;
    for (std::size_t k = 0; k < columns.size() - (with_error ? 0 : n_error_columns); ++k)
      names += (k == 0 ? "" : ",") + std::string(columns[k].name);
    if (with_contact)
      names += ",contacts,contacts_per_obstacle,largest_penetration,gs_iterations,gs_residual,normal_force,"
               "friction_force,t_contact,contact_work,friction_dissipation,compliance_lag,aim_error";
    return names;
  }

  void StepLog::add(const StepLogRow &row)
  {
    const auto        &columns = log_columns();
    std::ostringstream line;
    for (std::size_t k = 0; k < columns.size() - (with_error ? 0 : n_error_columns); ++k)
      {
        if (k > 0)
          line << ",";
        columns[k].write(line, row);
      }
    if (with_contact)
      {
        const auto  &s       = row.statistics;
        const auto  &c       = row.contact;
        const double seconds = s.stages.seconds(fem::stage::contact_detection) +
                               s.stages.seconds(fem::stage::contact_compliance) +
                               s.stages.seconds(fem::stage::contact_gauss_seidel) +
                               s.stages.seconds(fem::stage::contact_correction) +
                               s.stages.seconds(fem::stage::contact_penalty);
        line << "," << std::setprecision(6) << c.n_contacts << ",";
        // "12;3": the contacts of obstacle 1, 2, ... (a semicolon keeps the CSV's columns).
        for (std::size_t o = 0; o < c.contacts_per_obstacle.size(); ++o)
          line << (o > 0 ? ";" : "") << c.contacts_per_obstacle[o];
        line << "," << c.largest_penetration << ","
             << c.gauss_seidel.iterations << "," << c.gauss_seidel.residual << "," << c.normal_force << ","
             << c.friction_force << "," << seconds << "," << std::setprecision(10) << row.contact_work << ","
             << row.friction_dissipation << std::setprecision(6) << "," << c.compliance_lag << "," << c.aim_error;
      }
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
