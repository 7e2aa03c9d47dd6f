// A 1 m cube (OpenCASCADE kernel) with named top and bottom faces. Volume = 1 m^3.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
MeshSize{:} = 0.25;
Physical Volume("block") = {1};
Physical Surface("bottom") = {5};
Physical Surface("top") = {6};
