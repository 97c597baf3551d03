// Skin pad with a partial-depth incision slit; structured mesh (SI units): hexahedra for
// the accurate path, or (hexahedra = 0) each transfinite block cut into tetrahedra for
// the realtime path.
// Mesh with: gmsh -3 -format msh22 -o pad.msh skin_pad_incision.geo [-setnumber NAME value]
//
// The pad is split into 2 (x) x 3 (y) x 2 (z) transfinite blocks. The slit
// (x = 0, |y| <= Li/2, H-Di <= z <= H) is modelled by two distinct surfaces
// with two distinct top curves between the same corner points, so the wound
// faces get separate nodes while the crack front (shared curves) stays shared.
// Assumes 0 < Li < Ly and 0 < Di < H.
//
// Wg > 0 opens the wound (a fusiform defect, as after the excision of a lesion): the
// top edges of the wound faces become x = -/+ (Wg/2) cos(pi y / Li), meeting at the
// incision's ends; the faces are ruled down to the straight crack front at z = H - Di,
// so the gap narrows linearly with depth. The pad is stress-free in this state.
//
// layered = 1 tags the blocks below the incision's floor (z < H - Di) "hypodermis" and
// those above "dermis": a full-thickness skin wound, the cut through the dermis, over fat.

DefineConstant[
  Lx = {0.040,  Name "Parameters/Lx pad length in x [m]"},
  Ly = {0.030,  Name "Parameters/Ly pad width in y [m]"},
  H  = {0.006,  Name "Parameters/H pad thickness [m]"},
  Li = {0.020,  Name "Parameters/Li incision length in y [m]"},
  Di = {0.003,  Name "Parameters/Di incision depth from top [m]"},
  Wg = {0,      Name "Parameters/Wg wound gap at mid-incision top [m]"},
  layered = {0, Choices {0, 1}, Name "Parameters/layered: hypodermis under the incision's floor (1)"},
  h  = {0.0015, Name "Parameters/h target element size [m]"},
  hexahedra = {1, Choices {0, 1}, Name "Parameters/hexahedra (1) or tetrahedra (0)"}
];

// Duplicate curves/surfaces on the slit must not be merged.
Geometry.AutoCoherence = 0;

xs[] = {-Lx/2, 0, Lx/2};
ys[] = {-Ly/2, -Li/2, Li/2, Ly/2};
zs[] = {0, H - Di, H};

// Tag schemes (i, j, k index the x, y, z grid planes / blocks):
//   point   1 + i + 3j + 12k       x-curve 100 + i + 2j + 8k
//   y-curve 200 + i + 3j + 9k      z-curve 300 + i + 3j + 12k
//   x-face  400 + i + 3j + 9k      y-face  500 + i + 2j + 8k
//   z-face  600 + i + 2j + 6k      volume  700 + i + 2j + 6k
// Slit: curve 222 / face 413 belong to the x<0 side; their twins 250 / 450 to x>0.

For k In {0:2}
  For j In {0:3}
    For i In {0:2}
      Point(1 + i + 3*j + 12*k) = {xs[i], ys[j], zs[k], h};
    EndFor
  EndFor
EndFor

// Curves along x
For k In {0:2}
  For j In {0:3}
    For i In {0:1}
      Line(100 + i + 2*j + 8*k) = {1 + i + 3*j + 12*k, 2 + i + 3*j + 12*k};
    EndFor
  EndFor
EndFor
// Curves along y
For k In {0:2}
  For j In {0:2}
    For i In {0:2}
      Line(200 + i + 3*j + 9*k) = {1 + i + 3*j + 12*k, 4 + i + 3*j + 12*k};
    EndFor
  EndFor
EndFor
// Twin of the slit top curve 222 (same end points) for the x>0 side.
If (Wg > 0)
  // both top edges as splines through nw interior points of the cosine profile
  Delete { Curve{222}; }
  nw = 15;
  For side In {0:1}
    sign = (side == 0) ? -1 : 1;
    pts[] = {};
    pts[] += {1 + 1 + 3*1 + 12*2};
    For m In {1:nw}
      yy = -Li/2 + Li*m/(nw + 1);
      Point(1000 + 100*side + m) = {sign*(Wg/2)*Cos(Pi*yy/Li), yy, H, h};
      pts[] += {1000 + 100*side + m};
    EndFor
    pts[] += {4 + 1 + 3*1 + 12*2};
    If (side == 0)
      Spline(222) = pts[];
    Else
      Spline(250) = pts[];
    EndIf
  EndFor
Else
  Line(250) = {1 + 1 + 3*1 + 12*2, 4 + 1 + 3*1 + 12*2};
EndIf
// Curves along z
For k In {0:1}
  For j In {0:3}
    For i In {0:2}
      Line(300 + i + 3*j + 12*k) = {1 + i + 3*j + 12*k, 13 + i + 3*j + 12*k};
    EndFor
  EndFor
EndFor

// Faces normal to x
For k In {0:1}
  For j In {0:2}
    For i In {0:2}
      t = 400 + i + 3*j + 9*k;
      Curve Loop(t) = {200 + i + 3*j + 9*k, 300 + i + 3*(j+1) + 12*k,
                       -(200 + i + 3*j + 9*(k+1)), -(300 + i + 3*j + 12*k)};
      If (t == 413 && Wg > 0)
        Surface(t) = {t};
      Else
        Plane Surface(t) = {t};
      EndIf
    EndFor
  EndFor
EndFor
// Right-side slit face, bounded by the twin top curve.
Curve Loop(450) = {213, 319, -250, -316};
If (Wg > 0)
  Surface(450) = {450};
Else
  Plane Surface(450) = {450};
EndIf

// Faces normal to y
For k In {0:1}
  For j In {0:3}
    For i In {0:1}
      t = 500 + i + 2*j + 8*k;
      Curve Loop(t) = {100 + i + 2*j + 8*k, 300 + (i+1) + 3*j + 12*k,
                       -(100 + i + 2*j + 8*(k+1)), -(300 + i + 3*j + 12*k)};
      Plane Surface(t) = {t};
    EndFor
  EndFor
EndFor

// Faces normal to z
For k In {0:2}
  For j In {0:2}
    For i In {0:1}
      t = 600 + i + 2*j + 6*k;
      yl = 200 + i + 3*j + 9*k;       // y-curve at x index i
      yr = 200 + (i+1) + 3*j + 9*k;   // y-curve at x index i+1
      If (yl == 222 && i == 1)
        yl = 250;                     // top face of the x>0 middle block uses the twin
      EndIf
      Curve Loop(t) = {100 + i + 2*j + 8*k, yr, -(100 + i + 2*(j+1) + 8*k), -yl};
      Plane Surface(t) = {t};
    EndFor
  EndFor
EndFor

// Volumes
For k In {0:1}
  For j In {0:2}
    For i In {0:1}
      t = 700 + i + 2*j + 6*k;
      xl = 400 + i + 3*j + 9*k;
      If (xl == 413 && i == 1)
        xl = 450;                     // x>0 middle top block is bounded by the twin face
      EndIf
      Surface Loop(t) = {xl, 400 + (i+1) + 3*j + 9*k,
                         500 + i + 2*j + 8*k, 500 + i + 2*(j+1) + 8*k,
                         600 + i + 2*j + 6*k, 600 + i + 2*j + 6*(k+1)};
      Volume(t) = {t};
    EndFor
  EndFor
EndFor

// Node counts per curve; equal-length curves get equal counts, so shared faces conform.
nx  = Max(2, Round((Lx/2) / h) + 1);
nyo = Max(2, Round(((Ly - Li)/2) / h) + 1);
// >= 3 so the slit top curve has an interior node; otherwise both wound faces
// would consist of crack-front nodes only and the slit would not open.
nyi = Max(3, Round(Li / h) + 1);
nzb = Max(2, Round((H - Di) / h) + 1);
nzt = Max(2, Round(Di / h) + 1);

Transfinite Curve{100:123} = nx;
For k In {0:2}
  For i In {0:2}
    Transfinite Curve{200 + i + 9*k, 206 + i + 9*k} = nyo;
    Transfinite Curve{203 + i + 9*k} = nyi;
  EndFor
EndFor
Transfinite Curve{250} = nyi;
Transfinite Curve{300:311} = nzb;
Transfinite Curve{312:323} = nzt;

Transfinite Surface{:};
If (hexahedra)
  Recombine Surface{:};
EndIf
Transfinite Volume{:};

// Only these entities are written (interior interfaces stay untagged).
Physical Surface("bottom", 1) = {600:605};
Physical Surface("top", 2) = {612:617};
Physical Surface("wound_left", 3) = {413};
Physical Surface("wound_right", 4) = {450};
Physical Surface("sides", 5) = {400, 403, 406, 409, 412, 415,
                                402, 405, 408, 411, 414, 417,
                                500, 501, 508, 509, 506, 507, 514, 515};
If (layered)
  // the incision cuts the dermis through (Di its thickness); below it, hypodermis
  Physical Volume("dermis", 1) = {706:711};
  Physical Volume("hypodermis", 2) = {700:705};
Else
  Physical Volume("dermis", 1) = {700:711};
EndIf
