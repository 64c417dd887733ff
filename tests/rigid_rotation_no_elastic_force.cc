// A rigid motion of the rest mesh (a large rotation and a translation) must produce no
// elastic force: the polar decomposition recovers the rotation in every element, and the
// nodal rotations too. The linear model, which ignores rotations, does produce forces.
// An inverted element still gets a proper rotation (det = +1), as Irving et al. require.

#include "tests.h"

#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/rotations.h>
#include <warpchol/mesh/mesh_readers.h>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <cmath>

using namespace warpchol;

int main()
{
  dealii::Triangulation<3> triangulation;
  fem::read_mesh(std::string(SOURCE_DIR) + "/../meshes/sofa_liver.msh", triangulation);
  const fem::ElasticBody body(triangulation, fem::Material{50, 0.45, 20}, fem::MassMatrix::lumped,
                              std::vector<bool>(triangulation.n_vertices(), false));

  const fem::Matrix3 rotation =
    Eigen::AngleAxisd(2.0, fem::Vector3(1, -2, 0.5).normalized()).toRotationMatrix();
  const fem::Vector3        translation(0.3, -1.2, 4.0);
  std::vector<fem::Vector3> positions(body.n_vertices());
  for (unsigned int v = 0; v < body.n_vertices(); ++v)
    positions[v] = rotation * body.rest_positions()[v] + translation;

  std::vector<fem::Matrix3> element_rotations, nodal_rotations;
  body.compute_element_rotations(positions, element_rotations);
  body.compute_nodal_rotations(element_rotations, nodal_rotations);
  double element_rotation_error = 0, nodal_rotation_error = 0;
  for (const auto &r : element_rotations)
    element_rotation_error = std::max(element_rotation_error, (r - rotation).norm());
  for (const auto &r : nodal_rotations)
    nodal_rotation_error = std::max(nodal_rotation_error, (r - rotation).norm());
  tests::check_below("element rotations = the rigid rotation", element_rotation_error, 1e-12);
  tests::check_below("nodal rotations = the rigid rotation", nodal_rotation_error, 1e-12);

  // Force scale: what the same displacement would give without the rotation (linear).
  std::vector<fem::Vector3> corotated(body.n_vertices(), fem::Vector3::Zero());
  std::vector<fem::Vector3> linear(body.n_vertices(), fem::Vector3::Zero());
  body.add_elastic_forces(positions, &element_rotations, corotated);
  body.add_elastic_forces(positions, nullptr, linear);
  double largest_corotated = 0, largest_linear = 0;
  for (unsigned int v = 0; v < body.n_vertices(); ++v)
    {
      largest_corotated = std::max(largest_corotated, corotated[v].norm());
      largest_linear    = std::max(largest_linear, linear[v].norm());
    }
  tests::check_below("corotated elastic force / linear elastic force", largest_corotated / largest_linear, 1e-12);
  const double linear_energy = body.elastic_energy(positions, nullptr);
  tests::check_below("corotated elastic energy / linear elastic energy",
                     body.elastic_energy(positions, &element_rotations) / linear_energy, 1e-12);
  tests::check("the linear model sees a large energy (> 1 J)", linear_energy > 1);

  // An element pushed through its opposite face: F has det < 0; the rotation must be proper
  // and must reflect only along the thinnest direction.
  fem::Matrix3 inverted = fem::Matrix3::Identity();
  inverted(2, 2)        = -0.2;
  const fem::Matrix3 r  = fem::rotation_of(rotation * inverted);
  tests::check_below("inverted element: |det R - 1|", std::abs(r.determinant() - 1), 1e-12);
  tests::check_below("inverted element: R = the rigid rotation", (r - rotation).norm(), 1e-12);
}
