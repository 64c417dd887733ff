#include <warpchol/models/model_type.h>

#include <cmath>

namespace warpchol::fem
{
  std::string to_string(const ModelType type)
  {
    return name_of(model_type_names, type);
  }

  ModelType parse_model_type(const std::string &name)
  {
    return parse_name(model_type_names, name, "model type");
  }

  ElasticBody::Rotations rotations_of(const ModelType type)
  {
    switch (type)
      {
        case ModelType::linear:
          return ElasticBody::Rotations::none;
        case ModelType::corotational:
          return ElasticBody::Rotations::elements;
        case ModelType::stiffness_warping:
        case ModelType::warp_canceling:
          break;
      }
    return ElasticBody::Rotations::elements_and_vertices;
  }

  bool solves_in_nodal_frames(const ModelType type)
  {
    return type == ModelType::stiffness_warping || type == ModelType::warp_canceling;
  }

  bool reassembles_every_step(const ModelType type, const double rerotation_threshold)
  {
    return type == ModelType::corotational || (type == ModelType::warp_canceling && rerotation_threshold == 0);
  }

  bool reassembles_by_error_estimate(const ModelType type, const double rerotation_threshold)
  {
    return type == ModelType::warp_canceling && rerotation_threshold > 0 && !std::isinf(rerotation_threshold);
  }
} // namespace warpchol::fem
