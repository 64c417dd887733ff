#include <warpchol/base/exceptions.h>
#include <warpchol/models/contribution_frames.h>

#include <algorithm>
#include <string>

namespace warpchol::fem
{
  ContributionFrames::ContributionFrames(const unsigned int n_elements)
    : frames(n_elements)
    , stored(n_elements, 0)
    , element_rotations(n_elements, Matrix3::Identity())
  {}

  void ContributionFrames::reset(const std::vector<Matrix3> &rotations, const std::vector<Matrix3> *nodal_rotations)
  {
    // Referenced: an exact step keeps them at the cost of an exchange at the next step
    // (keep_rotations()), not of a copy of every rotation.
    referenced = &rotations;
    std::fill(stored.begin(), stored.end(), 0);
    reference_pending = nodal_rotations == nullptr;
    if (nodal_rotations)
      reference = *nodal_rotations;
    relative_due = true;
  }

  void ContributionFrames::keep_rotations(std::vector<Matrix3> &rotations)
  {
    if (referenced == nullptr)
      return;
    if (referenced != &rotations)
      throw Error("ContributionFrames::keep_rotations(): not the rotations reset() was given");
    element_rotations.swap(rotations);
    rotations.resize(element_rotations.size());
    referenced = nullptr;
  }

  const std::vector<Matrix3> &ContributionFrames::rotations() const
  {
    return referenced ? *referenced : element_rotations;
  }

  void ContributionFrames::adopt(std::vector<std::array<Matrix3, 4>> &made_frames)
  {
    frames.swap(made_frames);
    std::fill(stored.begin(), stored.end(), 1);
    reference.clear();
    reference_pending = false;
    relative_due      = true;
  }

  void ContributionFrames::update_solve_rotations(const ElasticBody &of_body, const std::vector<Matrix3> &rotations)
  {
    body         = &of_body;
    nodal        = &rotations;
    relative_due = true;
  }

  const std::vector<Matrix3> &ContributionFrames::solve_rotations() const
  {
    if (nodal == nullptr)
      throw Error("ContributionFrames::solve_rotations() before update_solve_rotations()");
    // The same rotations as the step of the reset would have computed: from its elements'.
    if (reference_pending)
      body->compute_nodal_rotations(rotations(), reference);
    reference_pending = false;
    if (reference.empty())
      return *nodal;
    if (reference.size() != nodal->size())
      throw Error("ContributionFrames: a reference of " + std::to_string(reference.size()) +
                  " vertices for nodal rotations of " + std::to_string(nodal->size()));
    if (relative_due)
      {
        relative.resize(nodal->size());
        for (std::size_t v = 0; v < nodal->size(); ++v)
          relative[v] = (*nodal)[v] * reference[v].transpose();
        relative_due = false;
      }
    return relative;
  }

  std::array<Matrix3, 4> ContributionFrames::of(const unsigned int e) const
  {
    if (stored[e])
      return frames[e];
    const Matrix3 &rotation = rotations()[e];
    return {{rotation, rotation, rotation, rotation}};
  }

  void ContributionFrames::rerotate(const unsigned int e, const std::array<unsigned int, 4> &vertices,
                                    const Matrix3 &element_rotation)
  {
    const std::vector<Matrix3> &solve = solve_rotations();
    for (unsigned int a = 0; a < 4; ++a)
      frames[e][a] = solve[vertices[a]].transpose() * element_rotation;
    stored[e] = 1;
  }

  ElementFrames ContributionFrames::element_frames() const
  {
    return ElementFrames::rerotated(frames, stored, rotations());
  }

  void ContributionFrames::save(BinaryWriter &writer) const
  {
    writer.section("contribution frames");
    writer.write(stored);
    // Only the frames in use: an element not re-rotated since the reset has its rotation.
    for (std::size_t e = 0; e < stored.size(); ++e)
      if (stored[e])
        writer.write(frames[e]);
    writer.write(rotations());
    writer.write(reference);
    writer.write(reference_pending);
  }

  void ContributionFrames::load(BinaryReader &reader)
  {
    reader.expect_section("contribution frames");
    const std::size_t n_elements = stored.size();
    reader.read(stored);
    if (stored.size() != n_elements)
      reader.fail("holds the frames of " + std::to_string(stored.size()) + " elements, the model keeps " +
                  std::to_string(n_elements));
    for (std::size_t e = 0; e < n_elements; ++e)
      if (stored[e])
        reader.read(frames[e]);
    referenced = nullptr;
    reader.read(element_rotations);
    reader.read(reference);
    reader.read(reference_pending);
    if (element_rotations.size() != n_elements)
      reader.fail("holds the rotations of " + std::to_string(element_rotations.size()) +
                  " elements, the model keeps " + std::to_string(n_elements));
  }
} // namespace warpchol::fem
