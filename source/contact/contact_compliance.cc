#include <warpchol/base/exceptions.h>
#include <warpchol/contact/contact_compliance.h>

#include <string>

#include "compliance_product_kernel.h"

namespace warpchol::fem
{
  namespace
  {
    /** The order of a square matrix of @p entries entries that has 3 rows per contact or vertex (0: none such). */
    std::size_t order_of(const std::size_t entries)
    {
      std::size_t order = 0;
      while (order * order < entries)
        ++order;
      return order * order == entries && order % 3 == 0 ? order : 0;
    }
  } // namespace

  ContactCompliance ContactCompliance::whole(std::vector<double> w)
  {
    ContactCompliance compliance;
    const std::size_t m = order_of(w.size());
    if (m == 0 && !w.empty())
      throw Error("ContactCompliance::whole(): W of " + std::to_string(w.size()) +
                  " entries is not m x m with 3 rows per contact");
    compliance.contact_count = m / 3;
    compliance.diagonal.resize(compliance.contact_count);
    for (std::size_t j = 0; j < compliance.contact_count; ++j)
      for (std::size_t c = 0; c < 3; ++c)
        for (std::size_t r = 0; r < 3; ++r)
          compliance.diagonal[j](r, c) = w[(3 * j + r) + (3 * j + c) * m];
    compliance.entries = std::move(w);
    return compliance;
  }

  ContactCompliance ContactCompliance::factored(const std::vector<double> &gram, std::vector<ContactRows> contacts)
  {
    ContactCompliance compliance;
    const Index       order = static_cast<Index>(order_of(gram.size()));
    if (order == 0 && !gram.empty())
      throw Error("ContactCompliance::factored(): G of " + std::to_string(gram.size()) +
                  " entries is not square over slots of 3 unknowns");
    compliance.gram          = &gram;
    compliance.order         = order;
    compliance.contact_count = contacts.size();
    compliance.diagonal.assign(compliance.contact_count, Matrix3::Zero());
    using Block = Eigen::Map<const Matrix3, 0, Eigen::OuterStride<>>;
    for (std::size_t j = 0; j < compliance.contact_count; ++j)
      {
        const ContactRows &contact = contacts[j];
        for (unsigned int a = 0; a < contact.n_parts; ++a)
          {
            if (contact.parts[a].slot < 0 || 3 * contact.parts[a].slot >= order)
              throw Error("ContactCompliance::factored(): contact " + std::to_string(j) + " on slot " +
                          std::to_string(contact.parts[a].slot) + " of " + std::to_string(order / 3));
            for (unsigned int b = 0; b < contact.n_parts; ++b)
              {
                const VertexRows &u = contact.parts[a], &v = contact.parts[b];
                const Block       g(gram.data() + 3 * u.slot + 3 * v.slot * order, Eigen::OuterStride<>(order));
                compliance.diagonal[j].noalias() += u.rows.transpose() * g * v.rows;
              }
          }
      }
    compliance.contact_rows = std::move(contacts);
    return compliance;
  }

  std::size_t ContactCompliance::n_contacts() const
  {
    return contact_count;
  }

  const Matrix3 &ContactCompliance::diagonal_block(const std::size_t j) const
  {
    return diagonal[j];
  }

  std::vector<double> ContactCompliance::times(const std::vector<double> &lambda) const
  {
    if (lambda.size() != 3 * contact_count)
      throw Error("ContactCompliance::times(): " + std::to_string(lambda.size()) + " impulses for " +
                  std::to_string(contact_count) + " contacts");
    return Product(*this, lambda).values();
  }

  std::vector<double> ContactCompliance::matrix() const
  {
    if (gram == nullptr)
      return entries;
    const std::size_t   m = 3 * contact_count;
    std::vector<double> w(m * m);
    for (std::size_t j = 0; j < contact_count; ++j)
      for (std::size_t c = 0; c < 3; ++c)
        {
          Product product(*this);
          product.add(j, Vector3::Unit(static_cast<Eigen::Index>(c)));
          for (std::size_t i = 0; i < contact_count; ++i)
            {
              const Vector3 u = product.velocity(i);
              for (std::size_t r = 0; r < 3; ++r)
                w[(3 * i + r) + (3 * j + c) * m] = u[r];
            }
        }
    return w;
  }

  ContactCompliance::Product::Product(const ContactCompliance &compliance)
    : compliance(compliance)
    , state(compliance.gram ? static_cast<std::size_t>(compliance.order) : 3 * compliance.contact_count, 0.)
  {}

  ContactCompliance::Product::Product(const ContactCompliance &compliance, const std::vector<double> &lambda)
    : Product(compliance)
  {
    for (std::size_t j = 0; j < compliance.contact_count; ++j)
      add(j, Vector3(lambda[3 * j], lambda[3 * j + 1], lambda[3 * j + 2]));
  }

  Vector3 ContactCompliance::Product::velocity(const std::size_t j) const
  {
    if (compliance.gram == nullptr)
      return Vector3(state[3 * j], state[3 * j + 1], state[3 * j + 2]);
    Vector3                               u    = Vector3::Zero();
    const ContactCompliance::ContactRows &rows = compliance.contact_rows[j];
    for (unsigned int a = 0; a < rows.n_parts; ++a)
      u.noalias() += rows.parts[a].rows.transpose() * Eigen::Map<const Vector3>(state.data() + 3 * rows.parts[a].slot);
    return u;
  }

  std::vector<double> ContactCompliance::Product::values() const
  {
    std::vector<double> result(3 * compliance.contact_count);
    for (std::size_t j = 0; j < compliance.contact_count; ++j)
      {
        const Vector3 u = velocity(j);
        for (std::size_t d = 0; d < 3; ++d)
          result[3 * j + d] = u[d];
      }
    return result;
  }

  void ContactCompliance::Product::add(const std::size_t j, const Vector3 &delta)
  {
    if (delta.isZero(0))
      return;
    // Three columns of W (or of G) times the change, fused into one pass over the state.
    const auto add_columns = [this](const double *columns, const std::size_t length, const Vector3 &times) {
      const double t[3] = {times[0], times[1], times[2]};
      add_three_columns(columns, length, t, state.data());
    };
    if (compliance.gram == nullptr)
      {
        const std::size_t m = 3 * compliance.contact_count;
        add_columns(compliance.entries.data() + 3 * j * m, m, delta);
        return;
      }
    const std::size_t                     s    = static_cast<std::size_t>(compliance.order);
    const ContactCompliance::ContactRows &rows = compliance.contact_rows[j];
    for (unsigned int b = 0; b < rows.n_parts; ++b)
      add_columns(compliance.gram->data() + 3 * static_cast<std::size_t>(rows.parts[b].slot) * s, s,
                  rows.parts[b].rows * delta);
  }
} // namespace warpchol::fem
