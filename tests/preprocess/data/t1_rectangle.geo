// In the style of gmsh's tutorial t1: a rectangle 0.1 m x 0.3 m built from points, lines,
// a curve loop and a plane surface, with physical groups. Area = 0.03 m^2.
lc = 1e-2;
Point(1) = {0, 0, 0, lc};
Point(2) = {.1, 0, 0, lc};
Point(3) = {.1, .3, 0, lc};
Point(4) = {0, .3, 0, lc};
Line(1) = {1, 2};
Line(2) = {3, 2};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {4, 1, -2, 3};
Plane Surface(1) = {1};
Physical Curve("My boundary") = {1, 2, 4};
Physical Surface("My surface") = {1};
