// A circular tunnel in a square block of rock, 2D (gmsh 4.8 built-in kernel, metres).
// "near": the rock around the opening, an annulus r0 < r < Rp, filled with bonded particles;
// "far": the rest of the block, meshed with finite elements. They meet on the circle r = Rp.
L = 0.045;    // half-width of the block
Rp = 0.015;   // outer radius of the particle region
r0 = 0.005;   // tunnel radius
lc = 0.004;   // geometry mesh size (strata sets the FEM sizes near the interface itself)

Point(1) = {-L, -L, 0, lc}; Point(2) = {L, -L, 0, lc}; Point(3) = {L, L, 0, lc}; Point(4) = {-L, L, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Point(5) = {0, 0, 0, lc};
Point(6) = {Rp, 0, 0, lc}; Point(7) = {0, Rp, 0, lc}; Point(8) = {-Rp, 0, 0, lc}; Point(9) = {0, -Rp, 0, lc};
Circle(5) = {6, 5, 7}; Circle(6) = {7, 5, 8}; Circle(7) = {8, 5, 9}; Circle(8) = {9, 5, 6};
Point(10) = {r0, 0, 0, lc}; Point(11) = {0, r0, 0, lc}; Point(12) = {-r0, 0, 0, lc}; Point(13) = {0, -r0, 0, lc};
Circle(9) = {10, 5, 11}; Circle(10) = {11, 5, 12}; Circle(11) = {12, 5, 13}; Circle(12) = {13, 5, 10};
Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {5, 6, 7, 8};
Curve Loop(3) = {9, 10, 11, 12};
Plane Surface(1) = {1, 2};
Plane Surface(2) = {2, 3};
Physical Surface("far") = {1};
Physical Surface("near") = {2};
