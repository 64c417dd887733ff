#include <warpchol/reports/kernel_timing.h>
#include <warpchol/base/format.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/fem/rotations.h>
#include <warpchol/fem/system_matrix.h>

#include <algorithm>
#include <functional>
#include <iomanip>
#include <limits>

namespace warpchol::app
{
  KernelTimes time_kernels(const Scene &scene, const std::vector<fem::Vector3> &positions)
  {
    const auto        &body       = scene.body();
    const unsigned int n_elements = body.n_elements();
    const auto         ns_per_tet = [&](const std::function<void()> &kernel) {
      double best = std::numeric_limits<double>::infinity();
      for (unsigned int repetition = 0; repetition < 5; ++repetition)
        {
          const Stopwatch stopwatch;
          kernel();
          best = std::min(best, stopwatch.seconds());
        }
      return 1e9 * best / n_elements;
    };
    KernelTimes               times;
    std::vector<fem::Matrix3> rotations(n_elements), gradients(n_elements);
    times.svd_rotation = ns_per_tet([&] {
      for (unsigned int e = 0; e < n_elements; ++e)
        rotations[e] = fem::rotation_by_svd(body.deformation_gradient(e, positions));
    });
    times.polar_rotation = ns_per_tet([&] {
      for (unsigned int e = 0; e < n_elements; ++e)
        rotations[e] = fem::rotation_of(body.deformation_gradient(e, positions));
    });
    for (unsigned int e = 0; e < n_elements; ++e)
      gradients[e] = body.deformation_gradient(e, positions);
    times.batched_rotation = ns_per_tet([&] { fem::rotations_of(gradients.data(), rotations.data(), n_elements); });
    fem::ElasticBody::State state;
    times.fused_pass = ns_per_tet([&] { body.evaluate(positions, fem::ElasticBody::Rotations::elements, state); });
    times.fused_pass_nodal =
      ns_per_tet([&] { body.evaluate(positions, fem::ElasticBody::Rotations::elements_and_vertices, state); });
    std::vector<fem::Vector3> product(body.n_vertices());
    fem::ElasticBody::ForceWork work;
    times.corotated_product =
      ns_per_tet([&] { body.corotated_stiffness_times(&state.element_rotations, positions, product, work); });
    // A from R_e K_e R_e^T, as the exact path assembles it in every step, and re-assembled
    // for a tenth of the elements (spread over the body), as a WCC update does.
    const auto                   &time_stepping = scene.parameters().time_stepping;
    const fem::SystemCoefficients coefficients  = fem::SystemCoefficients::implicit_euler(
      time_stepping.time_step, time_stepping.rayleigh_mass, time_stepping.rayleigh_stiffness);
    fem::SystemMatrix system(body, coefficients);
    times.assembly = ns_per_tet([&] { system.assemble(fem::ElementFrames::rotated(state.element_rotations)); });
    std::vector<unsigned int> tenth;
    for (unsigned int e = 0; e < n_elements; e += 10)
      tenth.push_back(e);
    times.reassembly_of_a_tenth =
      ns_per_tet([&] { system.reassemble(tenth, fem::ElementFrames::rotated(state.element_rotations)); });
    return times;
  }

  void print_kernel_table(std::ostream &out, const std::vector<std::pair<std::string, KernelTimes>> &columns,
                          const unsigned int n_elements, const double estimate_ns_per_tet,
                          const std::string &default_target)
  {
    const auto default_column =
      std::find_if(columns.begin(), columns.end(), [&](const auto &column) { return column.first == default_target; });
    const bool with_ratio = columns.size() > 1 && default_column != columns.end();
    const std::pair<const char *, double KernelTimes::*> rows[] = {
      {"rotation by SVD (the former kernel)           ", &KernelTimes::svd_rotation},
      {"rotation by scaled Newton, one by one         ", &KernelTimes::polar_rotation},
      {"rotation by scaled Newton, 8 per SIMD group   ", &KernelTimes::batched_rotation},
      {"fused pass: F, rotation, force, energy, gather", &KernelTimes::fused_pass},
      {"the same with the nodal rotations             ", &KernelTimes::fused_pass_nodal},
      {"corotated stiffness product (one CG product)  ", &KernelTimes::corotated_product},
      {"assembly of A from the rotations (exact path) ", &KernelTimes::assembly},
      {"re-assembly of every tenth element (per tet)  ", &KernelTimes::reassembly_of_a_tenth}};
    out << "element kernels (ns per tet, " << n_elements << " tets, one pass over all)";
    if (columns.size() > 1 || !columns.front().first.empty())
      {
        out << "\n  " << std::string(46, ' ');
        for (const auto &column : columns)
          out << " " << std::setw(9) << column.first;
        if (with_ratio)
          out << "  " << default_target << " / fastest";
      }
    out << ":\n";
    for (const auto &[label, member] : rows)
      {
        out << "  " << label;
        double fastest = std::numeric_limits<double>::infinity();
        for (const auto &column : columns)
          {
            out << " " << std::setw(9) << format_number(column.second.*member, 3);
            fastest = std::min(fastest, column.second.*member);
          }
        if (with_ratio)
          {
            const double ratio = default_column->second.*member / fastest;
            out << "  " << std::setw(9) << format_number(ratio, 3) << (ratio > 1.15 ? " slow" : "");
          }
        out << "\n";
      }
    out << "  WCC error estimate (fastest of the runs)      "
        << (estimate_ns_per_tet > 0 ? format_number(estimate_ns_per_tet, 3) : std::string("-")) << "\n";
  }
} // namespace warpchol::app
