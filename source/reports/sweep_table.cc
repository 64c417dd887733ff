#include <warpchol/reports/sweep_table.h>
#include <warpchol/base/format.h>

#include <algorithm>
#include <functional>
#include <iomanip>

namespace warpchol::app
{
  std::string threshold_text(const SweepRow &row)
  {
    return row.has_threshold ? format_number(row.threshold) : std::string("-");
  }

  void print_sweep_table(std::ostream &out, const AllParameters &parameters, const std::vector<SweepRow> &rows,
                         const double exact_per_step)
  {
    out << "scene " << parameters.scene_name() << ", " << parameters.time_stepping.n_steps
        << " steps, " << parameters.solver.settings.n_threads << " thread(s); error = max_i "
        << "|x_i - x_i(corotational)| / max_i |x_i(corotational) - X_i|, RMS = sqrt(mean_i "
        << "|x_i - x_i(corotational)|^2) / the same; max and mean over the steps; phases in ms "
        << "per step\n"
        << std::setw(24) << "model" << std::setw(10) << "threshold" << std::setw(9) << "rerot%"
        << std::setw(8) << "flops%" << std::setw(7) << "CG it" << std::setw(10) << "s/step"
        << std::setw(8) << "speedup" << std::setw(9) << "rotat" << std::setw(9) << "estim"
        << std::setw(9) << "assem" << std::setw(9) << "factor" << std::setw(9) << "iterat"
        << std::setw(9) << "solve" << std::setw(8) << "MiB" << std::setw(8) << "CG MB" << std::setw(8) << "CG GB/s"
        << std::setw(10) << "max err" << std::setw(10) << "mean err"
        << std::setw(10) << "max RMS" << std::setw(10) << "mean RMS" << "\n";
    for (const auto &row : rows)
      {
        const double per_step    = row.steps > 0 ? row.seconds / row.steps : 0;
        const auto   per_step_ms = [&](const double seconds) {
          return format_number(row.steps > 0 ? 1e3 * seconds / row.steps : 0, 3);
        };
        const auto &p     = row.phases;
        const auto  error = [&](const double value) {
          return row.model == fem::to_string(fem::ModelType::corotational) ? std::string("0") :
                                                                             format_number(value, 2);
        };
        out << std::setw(24) << row.model << std::setw(10) << threshold_text(row) << std::setw(9)
            << format_number(row.elements_rerotated, 3) << std::setw(8)
            << format_number(row.flops_recomputed, 3) << std::setw(7)
            << format_number(row.cg_iterations, 2) << std::setw(10) << format_number(per_step, 3)
            << std::setw(8) << format_number(per_step > 0 ? exact_per_step / per_step : 0, 3)
            << std::setw(9) << per_step_ms(p.t_rotations()) << std::setw(9)
            << per_step_ms(p.t_error_estimate()) << std::setw(9) << per_step_ms(p.t_assembly())
            << std::setw(9) << per_step_ms(p.t_factor()) << std::setw(9) << per_step_ms(p.t_iterations())
            << std::setw(9) << per_step_ms(p.t_solve()) << std::setw(8) << format_number(row.factor_mib, 3)
            << std::setw(8) << format_number(row.cg_iteration_mb, 3) << std::setw(8) << format_number(row.cg_gbps, 3)
            << std::setw(10) << error(row.error.max_error())
            << std::setw(10) << error(row.error.mean_error()) << std::setw(10)
            << error(row.error.max_rms_error()) << std::setw(10) << error(row.error.mean_rms_error())
            << (row.failure.empty() ? "" : "  " + row.failure) << "\n";
      }
  }

  void print_sweep_best(std::ostream &out, const std::vector<SweepRow> &rows, const double exact_per_step)
  {
    const auto describe = [&](const std::string &label, const SweepRow *row) {
      out << label;
      if (row == nullptr)
        {
          out << "none\n";
          return;
        }
      const double per_step = row->seconds / std::max(1u, row->steps);
      out << row->model << " " << threshold_text(*row) << ": " << format_number(per_step, 3) << " s/step, "
          << format_number(exact_per_step / per_step, 3) << "x, max error "
          << format_number(row->error.max_error(), 2) << ", CG it " << format_number(row->cg_iterations, 2)
          << "\n";
    };
    const auto fastest = [&](const std::function<bool(const SweepRow &)> &eligible) {
      const SweepRow *best = nullptr;
      for (std::size_t k = 1; k < rows.size(); ++k)
        if (rows[k].failure.empty() && rows[k].steps > 0 && rows[k].error.max_error() <= 0.01 &&
            eligible(rows[k]) && (best == nullptr || rows[k].seconds < best->seconds))
          best = &rows[k];
      return best;
    };
    out << "exact (corotational): " << format_number(exact_per_step, 3) << " s/step\n";
    describe("best at <= 1 % error: ", fastest([](const SweepRow &) { return true; }));
    describe("auto at <= 1 % error: ", fastest([](const SweepRow &row) { return row.model == "wcc_auto"; }));
    describe("background at <= 1 % error: ",
             fastest([](const SweepRow &row) { return row.model == "wcc_background"; }));
  }

  void write_sweep_csv(const std::vector<SweepRow> &rows, std::ostream &out)
  {
    out << "model,threshold,steps,elements_rerotated_pct,flops_recomputed_pct,cg_iterations,seconds,"
           "seconds_per_step,t_rotations,t_error_estimate,t_assembly,t_factor,t_iterations,t_solve,"
           "max_error_vs_corotational,mean_error_vs_corotational,max_rms_error_vs_corotational,"
           "mean_rms_error_vs_corotational,final_error_vs_corotational,factor_mib,cg_iteration_mb,cg_gbps,failure\n";
    for (const auto &row : rows)
      {
        const auto per_step_ms = [&](const double seconds) {
          return format_number(row.steps > 0 ? 1e3 * seconds / row.steps : 0, 3);
        };
        const auto &p = row.phases;
        const auto &e = row.error;
        out << row.model << "," << format_number(row.threshold) << "," << row.steps << ","
            << format_number(row.elements_rerotated, 4) << "," << format_number(row.flops_recomputed, 4) << ","
            << format_number(row.cg_iterations, 3) << "," << format_number(row.seconds, 4) << ","
            << format_number(row.steps > 0 ? row.seconds / row.steps : 0, 4) << ","
            << per_step_ms(p.t_rotations()) << "," << per_step_ms(p.t_error_estimate()) << ","
            << per_step_ms(p.t_assembly()) << "," << per_step_ms(p.t_factor()) << ","
            << per_step_ms(p.t_iterations()) << "," << per_step_ms(p.t_solve()) << ","
            << format_number(e.max_error(), 3) << "," << format_number(e.mean_error(), 3) << ","
            << format_number(e.max_rms_error(), 3) << "," << format_number(e.mean_rms_error(), 3) << ","
            << format_number(e.last_error(), 3) << "," << format_number(row.factor_mib, 4) << ","
            << format_number(row.cg_iteration_mb, 4) << "," << format_number(row.cg_gbps, 4) << ","
            << (row.failure.empty() ? "" : "\"" + row.failure + "\"") << "\n";
      }
  }
} // namespace warpchol::app
