#pragma once

#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/small_dense.h>
#include <warpchol/surgery/instrument_path.h>

#include <array>
#include <utility>
#include <vector>

/**
 * @file
 * A scalpel's cut: the tetrahedra a moving blade crosses.
 */
namespace warpchol::fem
{
  /**
   * A blade: the segment from @p start to @p end (its cutting edge) swept along
   * @p velocity from time @p begin for @p duration. Within a time step it sweeps the
   * parallelogram between its edge at the step's start and at its end; every tetrahedron
   * that parallelogram crosses (in the configuration of the step's start) is cut.
   *
   * With a @p path (values: the edge's two ends), the edge follows it instead from begin
   * to begin + duration, and a step sweeps one quadrilateral per stretch between the
   * path's samples: a curved incision is cut along its curve, not along its chords.
   */
  struct Blade
  {
    Vector3        start    = Vector3::Zero();
    Vector3        end      = Vector3::Zero();
    Vector3        velocity = Vector3::Zero();
    double         begin    = 0;
    double         duration = 0;
    InstrumentPath path;

    /** The edge at time @p time (held where it was before begin and after begin + duration). */
    std::pair<Vector3, Vector3> edge_at(double time) const;

    /** Whether the blade moves during (@p from, @p to]. */
    bool moves_during(double from, double to) const;
  };

  /**
   * Whether tetrahedron @p tetrahedron and triangle @p triangle overlap, by separating axes:
   * the triangle's normal, the tetrahedron's face normals and the cross products of their
   * edges. Sets that only touch (an overlap below 1e-12 of their size along an axis) do not
   * count: a blade that grazes a vertex or a face cuts nothing.
   */
  bool tetrahedron_meets_triangle(const std::array<Vector3, 4> &tetrahedron, const std::array<Vector3, 3> &triangle);

  /**
   * The elements of @p body at @p positions that the blade crosses during (@p from, @p to]
   * (sorted), leaving out those with @p cut[e] true.
   */
  std::vector<unsigned int> elements_crossed(const ElasticBody &body, const std::vector<Vector3> &positions,
                                             const Blade &blade, double from, double to,
                                             const std::vector<bool> &cut);
} // namespace warpchol::fem
