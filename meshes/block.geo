// A tissue block Lx x Ly x H (SI units), bottom face at z = 0, centred on x = y = 0.
// Mesh with: gmsh -3 -format msh22 -o block.msh block.geo [-setnumber NAME value]
//
// hexahedra = 1: structured hexahedra (transfinite bottom face extruded in layers), for
//   the accurate path; hexahedra = 0: unstructured tetrahedra of size h (Delaunay), for
//   the realtime path. At the defaults (40 x 40 x 10 mm, h = 2.2 mm) the tetrahedral mesh
//   has about 2000 vertices and 7000 tetrahedra, the size of seed 004's headline scene.

DefineConstant[
  Lx = {0.040,  Name "Parameters/Lx block length in x [m]"},
  Ly = {0.040,  Name "Parameters/Ly block width in y [m]"},
  H  = {0.010,  Name "Parameters/H block thickness [m]"},
  h  = {0.0022, Name "Parameters/h target element size [m]"},
  hexahedra = {0, Choices {0, 1}, Name "Parameters/hexahedra (1) or tetrahedra (0)"}
];

Point(1) = {-Lx/2, -Ly/2, 0, h};
Point(2) = { Lx/2, -Ly/2, 0, h};
Point(3) = { Lx/2,  Ly/2, 0, h};
Point(4) = {-Lx/2,  Ly/2, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

If (hexahedra)
  Transfinite Curve{1, 3} = Max(2, Round(Lx / h) + 1);
  Transfinite Curve{2, 4} = Max(2, Round(Ly / h) + 1);
  Transfinite Surface{1};
  Recombine Surface{1};
  out[] = Extrude {0, 0, H} { Surface{1}; Layers{Max(1, Round(H / h))}; Recombine; };
Else
  out[] = Extrude {0, 0, H} { Surface{1}; };
EndIf

// out[0]: top face, out[1]: volume, out[2..5]: the sides along curves 1..4.
Physical Surface("bottom", 1) = {1};
Physical Surface("top", 2) = {out[0]};
Physical Surface("sides", 3) = {out[2], out[3], out[4], out[5]};
Physical Volume("tissue", 1) = {out[1]};
