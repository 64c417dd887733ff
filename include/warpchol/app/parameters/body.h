#pragma once

#include <warpchol/app/parameters/entries.h>
#include <warpchol/app/parameters/parameter_file.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/small_dense.h>
#include <warpchol/mesh/cell_order.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/models/model_type.h>

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <vector>

/**
 * @file
 * The subsections of the body: its mesh ("Mesh"), its material ("Material") and its copies
 * side by side ("Bodies").
 */
namespace warpchol::app
{
  namespace parameters
  {
    /** Subsection "Mesh": a generated torus or box, or a mesh file. */
    struct Mesh
    {
      /** "torus", "box", "cylinder", "tube" or "file". */
      std::string           source = "torus";
      /** The mesh file as written in the parameter file. */
      std::string           file_name;
      double                scale = 1;
      /** Global refinements of a mesh read from a file (each tetrahedron into 8). */
      unsigned int          refinements = 0;
      /** The cells' and the unknowns' order (fem::order_cells_for_locality()). */
      fem::CellOrderChoice  cell_order = fem::CellOrderChoice::automatic;
      fem::TorusGeometry    torus;
      fem::BoxGeometry      box;
      fem::CylinderGeometry cylinder;
      fem::TubeGeometry     tube;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /** Subsection "Material". */
    struct Material
    {
      double          youngs_modulus = 50;
      double          poisson_ratio  = 0.45;
      double          density        = 20;
      /** > 0: the density is set so that the body has this mass (kg), density is unused. */
      double          total_mass  = 0;
      fem::MassMatrix mass_matrix = fem::MassMatrix::lumped;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /**
     * Subsection "Bodies": copies of the mesh side by side, each with its own model and
     * re-rotation threshold, each solved on its own (the report's side-by-side stability
     * figures: three tori with no update, a moderate threshold and exact corotation). Every
     * copy is the same scene (regions, loads, initial state) in its own frame; copy i is
     * shown shifted by i times the spacing in the one VTU series.
     */
    struct Bodies
    {
      unsigned int             count   = 1;
      fem::Vector3             spacing{0, 0, 0};
      /** One model type per body; empty: Model/Type for all. */
      std::vector<fem::ModelType> model_types;
      /** One threshold per body; empty: Model/Rerotation threshold for all. */
      std::vector<double>      rerotation_thresholds;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };
  } // namespace parameters
} // namespace warpchol::app
