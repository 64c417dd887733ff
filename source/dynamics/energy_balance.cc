#include <warpchol/dynamics/energy_balance.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace warpchol::fem
{
  EnergyBalance::EnergyBalance(const ElasticBody &body)
    : noise_floor(0.5 * body.material().youngs_modulus * body.total_volume() * 1e-16)
  {}

  void EnergyBalance::record(const ImplicitEuler &integrator, const ElasticEnergy elastic)
  {
    const double potential = integrator.potential_energy();
    held   = integrator.kinetic_energy() + integrator.tool_energy() +
           (elastic == ElasticEnergy::current ? integrator.elastic_energy() :
                                                integrator.elastic_energy_at_step_start());
    // The contacts' impulses: what moving obstacles did, less what friction dissipated.
    put_in = integrator.initial_energy() + integrator.external_work() + integrator.change_energy() +
             integrator.contact_work() - potential;
    finite = finite && std::isfinite(held) && std::isfinite(put_in);
    if (std::isfinite(held))
      largest_held = std::max(largest_held, held);
    const double current = ratio();
    if (std::isfinite(current))
      largest_ratio = std::max(largest_ratio, current);
    else if (!std::isnan(current))
      largest_ratio = current;
  }

  double EnergyBalance::held_energy() const
  {
    return held;
  }

  double EnergyBalance::energy_put_in() const
  {
    return put_in;
  }

  double EnergyBalance::ratio() const
  {
    if (!std::isfinite(held) || !std::isfinite(put_in))
      return std::numeric_limits<double>::quiet_NaN();
    if (held <= noise_floor)
      return 0;
    if (!(put_in > 0))
      return std::numeric_limits<double>::infinity();
    return held / put_in;
  }

  double EnergyBalance::max_ratio() const
  {
    return largest_ratio;
  }

  double EnergyBalance::max_held_energy() const
  {
    return largest_held;
  }

  bool EnergyBalance::all_finite() const
  {
    return finite;
  }
  void EnergyBalance::save(BinaryWriter &writer) const
  {
    writer.section("energy balance");
    for (const double value : {noise_floor, held, put_in, largest_ratio, largest_held})
      writer.write(value);
  }

  void EnergyBalance::load(BinaryReader &reader)
  {
    reader.expect_section("energy balance");
    for (double *value : {&noise_floor, &held, &put_in, &largest_ratio, &largest_held})
      reader.read(*value);
  }
} // namespace warpchol::fem
