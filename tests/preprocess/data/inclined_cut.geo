// A rectangle 100 mm x 40 mm cut by an inclined line from (40, 0) to (60, 40) mm: the FEM
// region "fem" on the left, the particle region "dem" on the right; the interface is
// inclined at about 63 degrees to the x axis and to every lattice row.
Point(1) = {0, 0, 0}; Point(2) = {0.04, 0, 0}; Point(3) = {0.1, 0, 0};
Point(4) = {0.1, 0.04, 0}; Point(5) = {0.06, 0.04, 0}; Point(6) = {0, 0.04, 0};
Line(1) = {1, 2}; Line(2) = {2, 5}; Line(3) = {5, 6}; Line(4) = {6, 1};
Line(5) = {2, 3}; Line(6) = {3, 4}; Line(7) = {4, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2}; Plane Surface(2) = {2};
Physical Surface("fem") = {1};
Physical Surface("dem") = {2};
Physical Curve("interface") = {2};
