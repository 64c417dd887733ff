// The report's torus (section 5 of ../../shared/seed/report_fr.txt): major radius 0.30 m,
// minor radius 0.10 m, turning around the y axis like deal.II's GridGenerator::torus.
//
//   gmsh -3 torus.geo -o torus_fine.msh
//
// With Gmsh 4.8.4 and the element size below this gives torus_fine.msh: 3445 vertices and
// 14625 tetrahedra (the report's fine torus had 3420 vertices, 15856 tetrahedra). The
// file also holds Gmsh's surface triangles, edge lines and a point, which the reader skips.
SetFactory("OpenCASCADE");
major_radius = 0.30;
minor_radius = 0.10;
Torus(1) = {0, 0, 0, major_radius, minor_radius};
// OpenCASCADE's torus turns around z: turn it around the x axis so that it turns around y.
Rotate {{1, 0, 0}, {0, 0, 0}, Pi / 2} { Volume{1}; }

element_size = 0.027;
Mesh.CharacteristicLengthMin = element_size;
Mesh.CharacteristicLengthMax = element_size;
Mesh.Optimize = 1;
Mesh.MshFileVersion = 2.2;
