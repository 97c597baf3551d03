// a geometry gmsh cannot parse
Point(1) = {0, 0, 0, 0.001;
