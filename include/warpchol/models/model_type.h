#pragma once

#include <warpchol/base/named_values.h>
#include <warpchol/fem/elastic_body.h>

#include <string>

/**
 * @file
 * The elasticity models by name (Model/Type, Bodies/Models) and what each does in a step,
 * for the code that runs a model's steps without its ElasticityModel (distributed/) and
 * for the models themselves, so that the answer is written once.
 */
namespace warpchol::fem
{
  /** The elasticity models (the classes of models/, one per value). */
  enum class ModelType
  {
    /** LinearModel: the rest matrix, factored once. */
    linear,
    /** CorotationalModel: every element's rotation, A assembled and factored every step. */
    corotational,
    /** StiffnessWarpingModel: the rest matrix in the nodal frames, factored once. */
    stiffness_warping,
    /** WarpCancelingModel: the elements over the re-rotation threshold re-rotated, A partially refactored. */
    warp_canceling
  };

  /** The names of the models (base/named_values.h): "linear", "corotational", "stiffness_warping", "warp_canceling". */
  inline constexpr NameTable<ModelType, 4> model_type_names{{{ModelType::linear, "linear"},
                                                             {ModelType::corotational, "corotational"},
                                                             {ModelType::stiffness_warping, "stiffness_warping"},
                                                             {ModelType::warp_canceling, "warp_canceling"}}};

  /** "linear", "corotational", "stiffness_warping" or "warp_canceling". */
  std::string to_string(ModelType type);

  /** The model named @p name; throws InputError otherwise. */
  ModelType parse_model_type(const std::string &name);

  /** Which rotations the model's element pass needs: none (linear), the elements' (corotation), also the vertices'. */
  ElasticBody::Rotations rotations_of(ModelType type);

  /** Whether the model solves in the nodal frames, (S A S^T) v = rhs: stiffness warping and WCC. */
  bool solves_in_nodal_frames(ModelType type);

  /**
   * Whether A is assembled again in full every step: exact corotation, and WCC at @p
   * rerotation_threshold 0 (every element over it).
   */
  bool reassembles_every_step(ModelType type, double rerotation_threshold);

  /**
   * Whether A is re-assembled in part, element by element, by the error estimate: WCC with
   * a threshold between 0 (reassembles_every_step()) and inf (stiffness warping).
   */
  bool reassembles_by_error_estimate(ModelType type, double rerotation_threshold);
} // namespace warpchol::fem
