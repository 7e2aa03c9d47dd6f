// FEM | DEM | FEM with inclined interfaces: a particle strip "strip" (a parallelogram about
// 16 mm wide) between two FEM blocks "left" and "right" in a 90 mm x 40 mm rectangle. One
// particle region with two interfaces.
Point(1) = {0, 0, 0}; Point(2) = {0.035, 0, 0}; Point(3) = {0.051, 0, 0}; Point(4) = {0.09, 0, 0};
Point(5) = {0.09, 0.04, 0}; Point(6) = {0.061, 0.04, 0}; Point(7) = {0.045, 0.04, 0}; Point(8) = {0, 0.04, 0};
Line(1) = {1, 2}; Line(2) = {2, 7}; Line(3) = {7, 8}; Line(4) = {8, 1};
Line(5) = {2, 3}; Line(6) = {3, 6}; Line(7) = {6, 7};
Line(8) = {3, 4}; Line(9) = {4, 5}; Line(10) = {5, 6};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2}; Plane Surface(2) = {2};
Curve Loop(3) = {8, 9, 10, -6}; Plane Surface(3) = {3};
Physical Surface("left") = {1};
Physical Surface("strip") = {2};
Physical Surface("right") = {3};
