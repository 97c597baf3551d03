// The upper half (y >= 0) of a single-edge-notched tension plate, width W along x and
// height 2H, with a sharp notch of length a from the left edge at mid-height, one
// hexahedron thick (plane strain with both z faces held in z): the phase field's textbook
// case in the finite-strain tissue (benchmarks/sent_tissue). By symmetry the plate's
// mid-plane is the face y = 0: the ligament (x > a) is held in y there, the notch
// (x < a) is free, a slit's face. Cells of size h on a band 0 <= y <= band along the
// crack's path from a - band to the right edge, growing to `coarse` over `grade`: gmsh
// meshes triangles of twice these sizes, recombines them into quadrilaterals where it
// can, extrudes them into one layer of prisms and hexahedra through the thickness T, and
// subdivides every cell into hexahedra (its all-hexahedra subdivision), which halves the
// sizes and makes two layers.
// Mesh with: gmsh -3 -format msh22 -o sent_half.msh sent_half.geo [-setnumber NAME value]
//
// Physical surfaces: notch and ligament (y = 0, x < a and x > a), left (x = 0), right
// (x = W below the pin), pin (x = W, the top `pin` of it: a short face held in x, so
// that the plate cannot slide), top (y = H, loaded), z0, z1.

DefineConstant[
  W      = {0.010,   Name "Parameters/W plate width along x [m]"},
  H      = {0.020,   Name "Parameters/H half the plate's height [m]"},
  a      = {0.003,   Name "Parameters/a notch length [m]"},
  T      = {0.0001,  Name "Parameters/T thickness along z [m]"},
  h      = {0.00003, Name "Parameters/h cell size on the crack's path [m]"},
  band   = {0.0005,  Name "Parameters/band height of the fine band above the path [m]"},
  coarse = {0.001,   Name "Parameters/coarse cell size away from it [m]"},
  grade  = {0.003,   Name "Parameters/grade distance over which the cells grow [m]"},
  pin    = {0.0005,  Name "Parameters/pin length of the face held in x [m]"}
];

Point(1) = {0, 0, 0};
Point(2) = {a, 0, 0};
Point(3) = {W, 0, 0};
Point(4) = {W, H - pin, 0};
Point(5) = {W, H, 0};
Point(6) = {0, H, 0};
For i In {1 : 6}
  Line(i) = {i, i % 6 + 1};
EndFor
Curve Loop(1) = {1 : 6};
Plane Surface(1) = {1};

Field[1] = Box;
Field[1].VIn = 2 * h;
Field[1].VOut = 2 * coarse;
Field[1].XMin = a - band;
Field[1].XMax = W;
Field[1].YMin = 0;
Field[1].YMax = band;
Field[1].ZMin = -1;
Field[1].ZMax = 1;
Field[1].Thickness = grade;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;              // frontal-Delaunay
Mesh.RecombinationAlgorithm = 1; // blossom
Mesh.SubdivisionAlgorithm = 2;   // all hexahedra
Recombine Surface{1};
out[] = Extrude {0, 0, T} { Surface{1}; Layers{1}; Recombine; };

// out[0]: the face z = T, out[1]: the volume, out[2..7]: the sides along curves 1..6
Physical Surface("notch", 1) = {out[2]};
Physical Surface("ligament", 2) = {out[3]};
Physical Surface("right", 3) = {out[4]};
Physical Surface("pin", 4) = {out[5]};
Physical Surface("top", 5) = {out[6]};
Physical Surface("left", 6) = {out[7]};
Physical Surface("z0", 7) = {1};
Physical Surface("z1", 8) = {out[0]};
Physical Volume("tissue", 1) = {out[1]};
