#include <warpchol/reports/kernel_timing.h>
#include <warpchol/reports/machine.h>
#include <warpchol/base/format.h>
#include <warpchol/base/simd.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/fem/rotations.h>
#include <warpchol/fem/system_matrix.h>

#include <algorithm>
#include <functional>
#include <iomanip>
#include <limits>

namespace warpchol::app
{
  std::vector<KernelTimes> time_kernels_on_targets(const Scene &scene, const std::vector<fem::Vector3> &positions,
                                                   const std::vector<std::string> &targets, const unsigned int rounds)
  {
    const auto        &body       = scene.body();
    const unsigned int n_elements = body.n_elements();
    std::vector<fem::Matrix3> rotations(n_elements), gradients(n_elements);
    for (unsigned int e = 0; e < n_elements; ++e)
      gradients[e] = body.deformation_gradient(e, positions);
    fem::ElasticBody::State state;
    body.evaluate(positions, fem::ElasticBody::Rotations::elements, state);
    std::vector<fem::Vector3>  product(body.n_vertices());
    fem::ElasticBody::ForceWork work;
    // A from R_e K_e R_e^T, as the exact path assembles it in every step, and re-assembled
    // for a tenth of the elements (spread over the body), as a WCC update does.
    const auto                   &time_stepping = scene.parameters().time_stepping;
    const fem::SystemCoefficients coefficients  = fem::SystemCoefficients::implicit_euler(
      time_stepping.time_step, time_stepping.rayleigh_mass, time_stepping.rayleigh_stiffness);
    fem::SystemMatrix         system(body, coefficients);
    std::vector<unsigned int> tenth;
    for (unsigned int e = 0; e < n_elements; e += 10)
      tenth.push_back(e);
    fem::ElasticBody::State scratch;
    const std::pair<double KernelTimes::*, std::function<void()>> kernels[] = {
      {&KernelTimes::svd_rotation,
       [&] {
         for (unsigned int e = 0; e < n_elements; ++e)
           rotations[e] = fem::rotation_by_svd(body.deformation_gradient(e, positions));
       }},
      {&KernelTimes::polar_rotation,
       [&] {
         for (unsigned int e = 0; e < n_elements; ++e)
           rotations[e] = fem::rotation_of(body.deformation_gradient(e, positions));
       }},
      {&KernelTimes::batched_rotation, [&] { fem::rotations_of(gradients.data(), rotations.data(), n_elements); }},
      {&KernelTimes::fused_pass,
       [&] { body.evaluate(positions, fem::ElasticBody::Rotations::elements, scratch); }},
      {&KernelTimes::fused_pass_nodal,
       [&] { body.evaluate(positions, fem::ElasticBody::Rotations::elements_and_vertices, scratch); }},
      {&KernelTimes::corotated_product,
       [&] { body.corotated_stiffness_times(&state.element_rotations, positions, product, work); }},
      {&KernelTimes::assembly, [&] { system.assemble(fem::ElementFrames::rotated(state.element_rotations)); }},
      {&KernelTimes::reassembly_of_a_tenth,
       [&] { system.reassemble(tenth, fem::ElementFrames::rotated(state.element_rotations)); }}};

    // Kernel by kernel, the targets in turn within each round: a burst of load on a shared
    // machine then slows one round of one kernel on one target, not a target's column.
    std::vector<KernelTimes> times(targets.size());
    for (const auto &[member, kernel] : kernels)
      {
        std::vector<double> best(targets.size(), std::numeric_limits<double>::infinity());
        for (unsigned int round = 0; round < rounds; ++round)
          for (std::size_t t = 0; t < targets.size(); ++t)
            {
              if (!targets[t].empty())
                simd::use_target(targets[t]);
              for (unsigned int repetition = 0; repetition < 5; ++repetition)
                {
                  const Stopwatch stopwatch;
                  kernel();
                  best[t] = std::min(best[t], stopwatch.seconds());
                }
            }
        for (std::size_t t = 0; t < targets.size(); ++t)
          times[t].*member = 1e9 * best[t] / n_elements;
      }
    return times;
  }

  KernelTimes time_kernels(const Scene &scene, const std::vector<fem::Vector3> &positions)
  {
    return time_kernels_on_targets(scene, positions, {""}, 1).front();
  }

  DefaultTargets DefaultTargets::current()
  {
    return {simd::current_target(simd::Family::element), simd::current_target(simd::Family::assembly)};
  }

  void print_kernel_table(std::ostream &out, const std::vector<std::pair<std::string, KernelTimes>> &columns,
                          const unsigned int n_elements, const double estimate_ns_per_tet,
                          const DefaultTargets &defaults)
  {
    const auto column_of = [&](const std::string &target) {
      return std::find_if(columns.begin(), columns.end(), [&](const auto &column) { return column.first == target; });
    };
    const bool with_ratio = columns.size() > 1 && column_of(defaults.element) != columns.end() &&
                            column_of(defaults.assembly) != columns.end();
    struct Row
    {
      const char *label;
      double KernelTimes::*member;
      simd::Family         family;
    };
    const Row rows[] = {
      {"rotation by SVD (the former kernel)           ", &KernelTimes::svd_rotation, simd::Family::element},
      {"rotation by scaled Newton, one by one         ", &KernelTimes::polar_rotation, simd::Family::element},
      {"rotation by scaled Newton, 8 per SIMD group   ", &KernelTimes::batched_rotation, simd::Family::element},
      {"fused pass: F, rotation, force, energy, gather", &KernelTimes::fused_pass, simd::Family::element},
      {"the same with the nodal rotations             ", &KernelTimes::fused_pass_nodal, simd::Family::element},
      {"corotated stiffness product (one CG product)  ", &KernelTimes::corotated_product, simd::Family::element},
      {"assembly of A from the rotations (exact path) ", &KernelTimes::assembly, simd::Family::assembly},
      {"re-assembly of every tenth element (per tet)  ", &KernelTimes::reassembly_of_a_tenth,
       simd::Family::assembly}};
    out << "element kernels (ns per tet, " << n_elements << " tets, one pass over all)";
    if (columns.size() > 1 || !columns.front().first.empty())
      {
        out << "\n  " << std::string(46, ' ');
        for (const auto &column : columns)
          out << " " << std::setw(9) << column.first;
        if (with_ratio)
          out << "  default / fastest";
      }
    out << ":\n";
    for (const Row &row : rows)
      {
        out << "  " << row.label;
        double fastest = std::numeric_limits<double>::infinity();
        for (const auto &column : columns)
          {
            out << " " << std::setw(9) << format_number(column.second.*row.member, 3);
            fastest = std::min(fastest, column.second.*row.member);
          }
        if (with_ratio)
          {
            const std::string &target = row.family == simd::Family::assembly ? defaults.assembly : defaults.element;
            const double       ratio  = column_of(target)->second.*row.member / fastest;
            out << "  " << std::setw(8) << target << " " << std::setw(5) << format_number(ratio, 3)
                << (ratio > slow_default_ratio ? " slow" : "");
          }
        out << "\n";
      }
    // The estimate is measured in runs, not per target: a table without runs has no row for it.
    if (estimate_ns_per_tet > 0)
      out << "  WCC error estimate (fastest of the runs)      " << format_number(estimate_ns_per_tet, 3) << "\n";
  }
} // namespace warpchol::app
