// 04_coupled_wave: an FEM block (left) and a particle block (right) sharing the line
// x = 0.16 m, both 0.02 m high. `strata report wave` fills "dem" with 1 mm disks (plus the
// one-layer overlap) and meshes "fem" with gmsh so that FEM nodes sit on the overlap's
// particle centres; a plane P-wave launched at x = 0 crosses the overlap into the particles.
lc = 0.005;
Point(1) = {0, 0, 0, lc};    Point(2) = {0.16, 0, 0, lc};    Point(3) = {0.16, 0.02, 0, lc};
Point(4) = {0, 0.02, 0, lc}; Point(5) = {0.28, 0, 0, lc};    Point(6) = {0.28, 0.02, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {2, 5}; Line(6) = {5, 6}; Line(7) = {6, 3};
Curve Loop(1) = {1, 2, 3, 4};   Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2};  Plane Surface(2) = {2};
Physical Surface("fem") = {1};
Physical Surface("dem") = {2};
Physical Curve("interface") = {2};
