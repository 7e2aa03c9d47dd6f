// A strip 130 mm x 30 mm for a plane pulse crossing an inclined interface: the FEM region
// "fem" on the left (loaded on x = 0), the particle region "dem" on the right; the interface
// runs from (35, 0) to (50, 30) mm, 63.4 degrees to the x axis and to the lattice rows.
Point(1) = {0, 0, 0}; Point(2) = {0.035, 0, 0}; Point(3) = {0.13, 0, 0};
Point(4) = {0.13, 0.03, 0}; Point(5) = {0.05, 0.03, 0}; Point(6) = {0, 0.03, 0};
Line(1) = {1, 2}; Line(2) = {2, 5}; Line(3) = {5, 6}; Line(4) = {6, 1};
Line(5) = {2, 3}; Line(6) = {3, 4}; Line(7) = {4, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2}; Plane Surface(2) = {2};
Physical Surface("fem") = {1};
Physical Surface("dem") = {2};
