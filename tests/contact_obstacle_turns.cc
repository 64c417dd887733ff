// An obstacle that turns as it moves: a path of (time, x, y, z, rx, ry, rz) rotates it by
// the rotation vector about the path's point. First its geometry in closed form: a box
// turned a quarter about z and moved, its distance and normal, its edges and its drawing;
// a capsule's axis; the velocity of a point of a box spinning at pi/2 rad/s (omega x r).
// Then a wide flat box (12 x 12 cm) presses 2 mm onto the top of a block (10 x 10 x 5 cm,
// held at its bottom) and turns 0.2 rad about the vertical while pressed: with friction
// it twists the block's top with it, without friction it does not, and no step leaves
// more penetration than the tolerance.

#include <warpchol/contact/obstacle.h>

#include "contact_tests.h"
#include "tests.h"

#include <cmath>

using namespace warpchol;
using fem::Vector3;

namespace
{
  /** The largest distance between @p a and @p b. */
  double distance(const Vector3 &a, const Vector3 &b)
  {
    return (a - b).norm();
  }

  /** The block's top pressed by a 12 x 12 x 4 cm box with @p friction that turns 0.2 rad while pressed. */
  tests::PressedTop press_and_turn(const double friction, const double tolerance)
  {
    fem::Obstacle plate = fem::Obstacle::box(Vector3(0.05, 0.05, 0.071), Vector3(0.12, 0.12, 0.04));
    plate.set_friction(friction);
    // Down 3 mm (2 into the block), turn while pressed, hold, lift.
    plate.set_path(fem::InstrumentPath({0, 0.2, 0.4, 0.43, 0.46, 1},
                                       {0.05, 0.05, 0.071, 0, 0, 0,   0.05, 0.05, 0.068, 0, 0, 0,
                                        0.05, 0.05, 0.068, 0, 0, 0.2, 0.05, 0.05, 0.068, 0, 0, 0.2,
                                        0.05, 0.05, 0.09,  0, 0, 0.2, 0.05, 0.05, 0.09,  0, 0, 0.2},
                                       6));
    return tests::press_block_top(plate, tolerance);
  }
} // namespace

int main()
{
  const double quarter = std::acos(-1.) / 2;

  // A box 0.2 long in x, 0.1 in y and z, at the origin; at t = 1 moved to (1, 0, 0) and
  // turned a quarter about z: its long side lies along y.
  fem::Obstacle box = fem::Obstacle::box(Vector3::Zero(), Vector3(0.2, 0.1, 0.1));
  box.set_path(fem::InstrumentPath({0, 1}, {0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, quarter}, 6));
  const fem::Proximity inside = box.proximity(Vector3(1, 0.08, 0), 1);
  tests::check_below("turned box: distance of (1, 0.08, 0) from -0.02", std::abs(inside.distance + 0.02), 1e-12);
  tests::check_below("turned box: its normal there from (0, 1, 0)", distance(inside.normal, Vector3::UnitY()), 1e-12);
  const fem::Proximity outside = box.proximity(Vector3(1.07, 0, 0), 1);
  tests::check_below("turned box: distance of (1.07, 0, 0) from 0.02", std::abs(outside.distance - 0.02), 1e-12);
  // Half-way: turned 45 degrees, at (0.5, 0, 0); the corner (0.1, 0.05) at rest is at
  // (0.5 + (0.1 - 0.05) / sqrt 2, (0.1 + 0.05) / sqrt 2).
  const double half = std::sqrt(0.5);
  const Vector3 corner(0.5 + 0.05 * half, 0.15 * half, 0.05);
  double nearest_corner = 1;
  for (const auto &edge : box.sharp_edges(0.5))
    for (const Vector3 &end : edge)
      nearest_corner = std::min(nearest_corner, distance(end, corner));
  tests::check_below("turned box: an edge ends at the turned corner", nearest_corner, 1e-12);
  double drawn_corner = 1;
  for (const Vector3 &point : box.boundary(0.5).points)
    drawn_corner = std::min(drawn_corner, distance(point, corner));
  tests::check_below("turned box: its drawing has the turned corner", drawn_corner, 1e-12);

  // A capsule along x from (0, 0, 0) to (0.1, 0, 0), turned a quarter about z about its first end.
  fem::Obstacle capsule = fem::Obstacle::capsule(Vector3::Zero(), Vector3(0.1, 0, 0), 0.01);
  capsule.set_path(fem::InstrumentPath({0, 1}, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, quarter}, 6));
  tests::check_below("turned capsule: the axis point nearest (0.5, 0.05, 0) is (0, 0.05, 0)",
                     distance(capsule.core_point(Vector3(0.5, 0.05, 0), 1), Vector3(0, 0.05, 0)), 1e-12);

  // Spinning at pi/2 rad/s about z through the origin: the point (0.1, 0, 0) moves at
  // omega x r = (0, 0.1 pi/2, 0).
  fem::Obstacle spinning = fem::Obstacle::box(Vector3::Zero(), Vector3(0.2, 0.1, 0.1));
  spinning.set_path(fem::InstrumentPath({0, 1}, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, quarter}, 6));
  tests::check_below("spinning box: velocity of (0.1, 0, 0) from omega x r",
                     distance(spinning.velocity(Vector3(0.1, 0, 0), 0.5, 0.5 + 1e-7), Vector3(0, 0.1 * quarter, 0)),
                     1e-7);
  // Translated only (3 values a sample), as before: the velocity is the path's.
  fem::Obstacle sliding = fem::Obstacle::box(Vector3::Zero(), Vector3(0.2, 0.1, 0.1));
  sliding.set_path(fem::InstrumentPath({0, 1}, {0, 0, 0, 0.3, 0, 0}, 3));
  tests::check_below("sliding box: velocity (0.3, 0, 0) anywhere",
                     distance(sliding.velocity(Vector3(5, 6, 7), 0.2, 0.3), Vector3(0.3, 0, 0)), 1e-12);

  constexpr double         tolerance = 1e-5;
  const tests::PressedTop with_friction = press_and_turn(1, tolerance);
  const tests::PressedTop frictionless  = press_and_turn(0, tolerance);
  tests::check("friction 1: the plate twists the block's top with it (its corners turn counter-clockwise by "
               "0.05 to 0.2 rad, the plate's turn)",
               with_friction.largest_turn > 0.05 && with_friction.largest_turn <= 0.2);
  tests::check_below("frictionless: the top's corners turned (rad)", std::abs(frictionless.largest_turn), 1e-6);
  tests::check_below("largest penetration over the steps, friction 1 (m)", with_friction.largest_penetration, tolerance);
  tests::check_below("largest penetration over the steps, frictionless (m)", frictionless.largest_penetration,
                     tolerance);
  tests::check("the plate pushes back at its deepest", with_friction.force_at_depth > 0 && frictionless.force_at_depth > 0);
  tests::check("no contact once it has left", !with_friction.touching_at_end && !frictionless.touching_at_end);
}
