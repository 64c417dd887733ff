#pragma once

/**
 * @file
 * The headers that the simulation tests compile, parsed once per build into a precompiled
 * header (tests/CMakeLists.txt) rather than once per test: deal.II's finite elements, DoF
 * handlers and parameter handling, and the application classes over them. Without it, most
 * of each such test's compile time went into these headers. The tests still include what
 * they use; this header only saves the parsing.
 */

#include "simulation_tests.h"

#include <warpchol/contact/contact_constraints.h>
#include <warpchol/dynamics/energy_balance.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/mesh/mesh_readers.h>
#include <warpchol/models/corotational_model.h>
#include <warpchol/models/elasticity_model.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/full_matrix.h>

#include <Eigen/LU>

#include <iomanip>
#include <regex>
#include <sstream>
