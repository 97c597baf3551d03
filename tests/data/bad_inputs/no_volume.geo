// a geometry without any volume: gmsh meshes nothing in 3D
Point(1) = {0, 0, 0, 0.001};
Point(2) = {0.01, 0, 0, 0.001};
Line(1) = {1, 2};
