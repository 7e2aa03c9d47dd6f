// 04_coupled_wave, FEM | DEM | FEM: a particle strip embedded between two FEM blocks, all
// 0.02 m high. "fem" (x in [0, 0.2]) is loaded at x = 0; "dem" is a strip of 60 lattice row
// spacings (60 x 0.001*sqrt(3)/2 = 0.05196 m: both interfaces must lie on lattice rows of
// 1 mm disks); "fem_exit" (0.08 m) lies beyond it. `strata report wave --embedded` fills
// "dem" (plus one overlap layer into each FEM block) with 1 mm disks and meshes both FEM
// blocks as one mesh, so that the pulse enters the particles through one overlap and
// leaves them through the other.
L = 0.001 * Sqrt(3) / 2;
x1 = 0.2;
x2 = x1 + 60 * L;
x3 = x2 + 0.08;
h = 0.02;
Point(1) = {0, 0, 0};  Point(2) = {x1, 0, 0};  Point(3) = {x1, h, 0};  Point(4) = {0, h, 0};
Point(5) = {x2, 0, 0}; Point(6) = {x2, h, 0}; Point(7) = {x3, 0, 0};  Point(8) = {x3, h, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {2, 5}; Line(6) = {5, 6}; Line(7) = {6, 3};
Line(8) = {5, 7}; Line(9) = {7, 8}; Line(10) = {8, 6};
Curve Loop(1) = {1, 2, 3, 4};    Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2};   Plane Surface(2) = {2};
Curve Loop(3) = {8, 9, 10, -6};  Plane Surface(3) = {3};
Physical Surface("fem") = {1};
Physical Surface("dem") = {2};
Physical Surface("fem_exit") = {3};
Physical Curve("interface_in") = {2};
Physical Curve("interface_out") = {6};
