// Two rectangles sharing the line y = 0.05: "fem" below (0 <= y <= 0.05), "dem" above
// (0.05 <= y <= 0.1), both 0.1 m wide.
lc = 0.01;
Point(1) = {0, 0, 0, lc}; Point(2) = {0.1, 0, 0, lc}; Point(3) = {0.1, 0.05, 0, lc};
Point(4) = {0, 0.05, 0, lc}; Point(5) = {0.1, 0.1, 0, lc}; Point(6) = {0, 0.1, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {3, 5}; Line(6) = {5, 6}; Line(7) = {6, 4};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {-3, 5, 6, 7}; Plane Surface(2) = {2};
Physical Surface("fem") = {1};
Physical Surface("dem") = {2};
Physical Curve("interface") = {3};
