// A bar L x W x T (SI units) along x, its top face y = W dipping at mid-length by a
// Gaussian neck of relative depth `neck` and width `neck_width`, so that a tear under
// tension starts there (parameters/tearing/phase_field_bar.prm). Structured hexahedra:
// `nx` cells along x, `ny` across, one through the thickness (plane strain with both z
// faces held in z).
// Mesh with: gmsh -3 -format msh22 -o necked_bar.msh necked_bar.geo [-setnumber NAME value]
//
// Physical surfaces: x0, x1 (the ends), y0 (the straight side), y1 (the necked side),
// z0, z1.

DefineConstant[
  L    = {0.010, Name "Parameters/L bar length along x [m]"},
  W    = {0.001, Name "Parameters/W bar width along y [m]"},
  T    = {0.001, Name "Parameters/T bar thickness along z [m]"},
  neck = {0.02,  Name "Parameters/neck relative depth of the neck at mid-length [1]"},
  neck_width = {0.001, Name "Parameters/neck_width the neck's Gaussian width [m]"},
  nx   = {100,   Name "Parameters/nx cells along x [1]"},
  ny   = {5,     Name "Parameters/ny cells across y [1]"}
];

Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, W, 0};
Point(4) = {0, W, 0};
// the necked side from (L, W) back to (0, W) through 39 points inside
top[] = {3};
For i In {1 : 39}
  x = L * (1 - i / 40);
  p = newp;
  Point(p) = {x, W * (1 - neck * Exp(-((x - L / 2) / neck_width) ^ 2)), 0};
  top[] += {p};
EndFor
top[] += {4};
Line(1) = {1, 2};
Line(2) = {2, 3};
Spline(3) = top[];
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = nx + 1;
Transfinite Curve{2, 4} = ny + 1;
Transfinite Surface{1} = {1, 2, 3, 4};
Recombine Surface{1};
out[] = Extrude {0, 0, T} { Surface{1}; Layers{1}; Recombine; };

// out[0]: the face z = T, out[1]: the volume, out[2..5]: the sides along curves 1..4
Physical Surface("y0", 1) = {out[2]};
Physical Surface("x1", 2) = {out[3]};
Physical Surface("y1", 3) = {out[4]};
Physical Surface("x0", 4) = {out[5]};
Physical Surface("z0", 5) = {1};
Physical Surface("z1", 6) = {out[0]};
Physical Volume("tissue", 1) = {out[1]};
