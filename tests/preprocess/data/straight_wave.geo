// The strip of inclined_wave.geo with a straight interface x = 42.5 mm (normal to the
// strip): the same pulse through the box path's copies and the general path's
// interpolation, for comparison.
Point(1) = {0, 0, 0}; Point(2) = {0.0425, 0, 0}; Point(3) = {0.13, 0, 0};
Point(4) = {0.13, 0.03, 0}; Point(5) = {0.0425, 0.03, 0}; Point(6) = {0, 0.03, 0};
Line(1) = {1, 2}; Line(2) = {2, 5}; Line(3) = {5, 6}; Line(4) = {6, 1};
Line(5) = {2, 3}; Line(6) = {3, 4}; Line(7) = {4, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2}; Plane Surface(2) = {2};
Physical Surface("fem") = {1};
Physical Surface("dem") = {2};
