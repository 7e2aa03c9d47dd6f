// A 1 m cube for the large-model benchmark: one physical volume, and its top and bottom faces
// as physical surfaces (the loaded and the supported face).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Physical Volume("rock") = {1};
Physical Surface("bottom") = {5};
Physical Surface("top") = {6};
