#pragma once

#include <warpchol/base/types.h>
#include <warpchol/fem/small_dense.h>

#include <array>
#include <cstddef>
#include <vector>

/**
 * @file
 * The compliance W = H A~^-1 H^T of a contact step as Gauss-Seidel reads it: a 3 x 3 block
 * per contact on W's diagonal and the product W lambda kept up to date as the impulses
 * change. W is held either as its m x m entries (SOFA's way, or any compliance given whole)
 * or factored as W = D^T G D, G the block of A^-1 among the contact vertices' unknowns and
 * D the contacts' directions on their vertices, so that W's entries are never formed.
 */
namespace warpchol::fem
{
  /**
   * W of a contact step, 3 rows per contact (its normal, then two tangents).
   *
   * Factored, W's 3 x 3 block of contacts i and j is the sum over their vertices u, v of
   * D_iu^T G_uv D_jv: forming W would read G once per pair of contacts and write m^2
   * entries, as many as a Gauss-Seidel sweep reads. Instead, Gauss-Seidel keeps y = G D
   * lambda (|S| entries) and reads a contact's velocities from it: a sweep then costs what
   * it costs on W's entries (3 |S| multiply-adds per vertex of a contact whose impulse
   * changed, against 3 m on W), and nothing is formed.
   */
  class ContactCompliance
  {
  public:
    /**
     * A contact's three rows on one of its vertices: the vertex's slot in G (3 unknowns
     * each) and D = w R^T [n t_1 t_2].
     */
    struct VertexRows
    {
      Index   slot = 0;
      Matrix3 rows = Matrix3::Zero();
    };
    /**
     * A contact's rows on each of its vertices that have unknowns (1 to 3: a vertex, an
     * edge's or a triangle's point).
     */
    struct ContactRows
    {
      std::array<VertexRows, 3> parts;
      unsigned int              n_parts = 0;
    };

    /** W given whole: @p w is m x m, column-major, symmetric (m a multiple of 3). */
    static ContactCompliance whole(std::vector<double> w);

    /**
     * W = D^T G D: @p gram is G, column-major, square over slots of 3 unknowns (slots no
     * contact reads may be free: cholesky::KeptInverseColumns), which must outlive this
     * object and stay unchanged; @p contacts the rows of each contact on its vertices'
     * slots.
     */
    static ContactCompliance factored(const std::vector<double> &gram, std::vector<ContactRows> contacts);

    /** Contacts (m / 3). */
    std::size_t n_contacts() const;

    /** W's diagonal block of contact @p j. */
    const Matrix3 &diagonal_block(std::size_t j) const;

    /** W lambda. */
    std::vector<double> times(const std::vector<double> &lambda) const;

    /** W's m x m entries, column-major (tests and benchmarks; a factored W forms them here). */
    std::vector<double> matrix() const;

    /**
     * W lambda as Gauss-Seidel changes lambda one contact at a time: velocity(j) reads
     * contact j's rows of W lambda, add(j, delta) adds delta to its impulse.
     */
    class Product
    {
    public:
      /** lambda = 0. */
      explicit Product(const ContactCompliance &compliance);
      /** From @p lambda (3 per contact). */
      Product(const ContactCompliance &compliance, const std::vector<double> &lambda);
      /** Contact @p j's three rows of W lambda. */
      Vector3 velocity(std::size_t j) const;
      /** lambda_j += @p delta. */
      void add(std::size_t j, const Vector3 &delta);
      /** W lambda, 3 rows per contact. */
      std::vector<double> values() const;

    private:
      const ContactCompliance &compliance;
      /** Whole: W lambda (m). Factored: G D lambda (|S|). */
      std::vector<double> state;
    };

  private:
    ContactCompliance() = default;

    /** Whole: W's entries. */
    std::vector<double> entries;
    /** Factored: G (not owned), its order |S|, and each contact's rows. */
    const std::vector<double> *gram = nullptr;
    Index                      order = 0;
    std::vector<ContactRows>   contact_rows;
    /** The diagonal blocks, one per contact, and the number of contacts. */
    std::vector<Matrix3> diagonal;
    std::size_t          contact_count = 0;
  };
} // namespace warpchol::fem
