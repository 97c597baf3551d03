// Two pieces of tissue side by side (SI units), as in seed 001's Endo Stitch task: two
// flat pieces W x Ly x H, their facing edges a gap g apart across x = 0, bottom faces at
// z = 0, centred on y = 0. Each is clamped at its far edge ("outer") and free elsewhere.
// Mesh with: gmsh -3 -format msh22 -o pieces.msh two_pieces.geo [-setnumber NAME value]
//
// hexahedra = 1: structured hexahedra (transfinite faces extruded in layers); hexahedra
// = 0: unstructured tetrahedra of size h (Delaunay), for the realtime path.

DefineConstant[
  W  = {0.020,  Name "Parameters/W piece length in x [m]"},
  Ly = {0.010,  Name "Parameters/Ly piece width in y [m]"},
  H  = {0.003,  Name "Parameters/H piece thickness [m]"},
  g  = {0.001,  Name "Parameters/g gap between the facing edges [m]"},
  h  = {0.001,  Name "Parameters/h target element size [m]"},
  hexahedra = {0, Choices {0, 1}, Name "Parameters/hexahedra (1) or tetrahedra (0)"}
];

// piece s (0: x < 0, 1: x > 0) spans x from x0[s] to x1[s]; its outer edge is x0[0] or x1[1]
x0[] = {-g/2 - W, g/2};
x1[] = {-g/2, g/2 + W};

For s In {0:1}
  Point(1000*s + 1) = {x0[s], -Ly/2, 0, h};
  Point(1000*s + 2) = {x1[s], -Ly/2, 0, h};
  Point(1000*s + 3) = {x1[s],  Ly/2, 0, h};
  Point(1000*s + 4) = {x0[s],  Ly/2, 0, h};
  // lines 1000s+1: along x at -Ly/2, +2: at x1, +3: along x at +Ly/2, +4: at x0 (tags far apart: the extrusion numbers its own after the largest)
  Line(1000*s + 1) = {1000*s + 1, 1000*s + 2};
  Line(1000*s + 2) = {1000*s + 2, 1000*s + 3};
  Line(1000*s + 3) = {1000*s + 3, 1000*s + 4};
  Line(1000*s + 4) = {1000*s + 4, 1000*s + 1};
  Curve Loop(1000*s + 1) = {1000*s + 1, 1000*s + 2, 1000*s + 3, 1000*s + 4};
  Plane Surface(1000*s + 1) = {1000*s + 1};
  If (hexahedra)
    Transfinite Curve{1000*s + 1, 1000*s + 3} = Max(2, Round(W / h) + 1);
    Transfinite Curve{1000*s + 2, 1000*s + 4} = Max(2, Round(Ly / h) + 1);
    Transfinite Surface{1000*s + 1};
    Recombine Surface{1000*s + 1};
    out[] = Extrude {0, 0, H} { Surface{1000*s + 1}; Layers{Max(1, Round(H / h))}; Recombine; };
  Else
    out[] = Extrude {0, 0, H} { Surface{1000*s + 1}; };
  EndIf
  // out[0]: top, out[1]: volume, out[2..5]: the sides along lines 1000s+1..1000s+4
  top[s]    = out[0];
  volume[s] = out[1];
  along[s]  = out[2];
  x_end[s]  = out[3];
  across[s] = out[4];
  x_start[s] = out[5];
EndFor

Physical Surface("bottom", 1) = {1, 1001};
Physical Surface("top", 2) = {top[0], top[1]};
// the far edges, clamped; the facing edges, which the stitch draws together
Physical Surface("outer", 3) = {x_start[0], x_end[1]};
Physical Surface("edge_left", 4) = {x_end[0]};
Physical Surface("edge_right", 5) = {x_start[1]};
Physical Surface("sides", 6) = {along[0], across[0], along[1], across[1]};
Physical Volume("tissue", 1) = {volume[0], volume[1]};
