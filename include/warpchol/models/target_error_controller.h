#pragma once

#include <string>

/**
 * @file
 * WCC's re-rotation threshold steered toward a target error (Model/Target error).
 */
namespace warpchol::fem
{
  /**
   * Steers WCC's re-rotation threshold so that each step's velocity error against exact
   * corotation stays near a target, and gives up where no threshold holds it with few
   * re-rotations.
   *
   * After each step, its error e moves the next step's threshold by the factor
   * clamp((g / e)^0.7, 1/8, 2), g = target / 2 (in logarithms, a gain of 0.7 on an error
   * that grows like the threshold to a power of 0.6 to 1.1: it falls fast and rises
   * slowly), the threshold kept in [1e-6, 100] (above 100 hardly an element is ever
   * re-rotated: a body that rested and moves again is caught within steps).
   *
   * It gives up (thin bodies in bending, where the error of the few elements left adds up
   * along the swing) when
   * - the threshold went a hundred times below where it started while the steps re-rotate a
   *   quarter of the elements or more and still miss the goal (moving averages), or
   * - the step error was over four times the goal in three of the last five steps, or
   * - the steps hold the goal only by updating 40 % of the elements or more: a partial
   *   refactorization of that many elements' columns recomputes nearly all of a full
   *   one's flops (doc/calibration).
   * The model then iterates on the exact corotational matrix instead.
   */
  class TargetErrorController
  {
  public:
    /** Steer toward @p target_error (0: no target, the threshold stays @p start_threshold). */
    TargetErrorController(double target_error, double start_threshold);

    /** The target error; 0 when the threshold stays fixed. */
    double target() const;
    /** The threshold of the next step. */
    double threshold() const;
    /** Whether it steers the threshold: a target, not given up. */
    bool steering() const;
    /** Empty while it steers (or without a target); once it gave up, why and from which step. */
    const std::string &why_given_up() const;

    /**
     * Step @p step (from 1) is being prepared; the one before had velocity error
     * @p last_error against exact corotation and re-rotated the share @p rerotated_fraction of
     * the elements. Adapts threshold(); returns true if it gives up now.
     */
    bool steer(unsigned int step, double last_error, double rerotated_fraction);

    /** The checkpointed state, for BinaryWriter and BinaryReader alike. */
    template <typename Archive>
    void serialize(Archive &archive)
    {
      archive &adapted_threshold &recent_rerotated_fraction &recent_error_ratio &far_over_goal &given_up;
    }

  private:
    double       target_error;
    double       start_threshold;
    double       adapted_threshold;
    /** Moving averages of the share of elements re-rotated per step and of the step error over its goal. */
    double       recent_rerotated_fraction = 0;
    double       recent_error_ratio     = 0;
    /** Bit k set if the step error of k + 1 steps ago was far over the goal. */
    unsigned int far_over_goal = 0;
    std::string  given_up;
  };
} // namespace warpchol::fem
